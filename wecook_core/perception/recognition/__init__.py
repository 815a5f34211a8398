"""Action recognition (paper, "Action Recognition"): individual, transfer and collaborative actions, motion cues."""
