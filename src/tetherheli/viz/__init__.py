"""Figures and animation; these modules only read results."""
