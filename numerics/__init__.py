"""Numerical layer: generated code loaded and integrated in double or arbitrary precision."""
