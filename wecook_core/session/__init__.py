"""A session on disk: its inputs, cached observations and the journal of corrections."""
