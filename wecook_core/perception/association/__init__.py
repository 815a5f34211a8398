"""Object association (paper, "Object Association"): per-frame links, what each hand holds, per-segment summaries."""
