"""Multi-setup tests: one shape through the reference sensors (PoSER, PreGER), the references found
from the data, the pairing of modes across setups and the test's points and geometry."""
