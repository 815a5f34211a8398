"""Observations: importing (or detecting) object boxes and hand tracks into one checked value."""
