"""Figures. Every function here builds and returns a ``matplotlib.figure.Figure`` (no pyplot, no
global state, no display); callers save it. One module per topic."""
