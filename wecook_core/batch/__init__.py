"""Many videos at once: a manifest, one task per video and stage (on Ray), resumable, one report."""
