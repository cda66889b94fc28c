"""Examples for tests and demos, not the method: the paper's simulated cases (``paper_cases``), synthetic modal
systems (``synthetic``), the NASA grid of the built-in example (``grid``, also ``era.examples.grid``) and its simulated
test with a hidden effect (``grid_simulation``, also ``era.examples.grid_simulation``)."""
