"""The default analysis and the automatic choice of the structure's modes: the pipeline after the SVD,
the choice's rules and its evidence."""
