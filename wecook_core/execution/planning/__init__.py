"""Motion planning between configurations (OMPL RRTConnect, or straight lines), over any collision check."""
