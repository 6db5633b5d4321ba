"""Measurement chain: sine fit, comfort weighting."""
