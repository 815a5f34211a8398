"""Skills: what each verb's motion is (waypoints, actuation paths) and where it may be done (Task Space Regions)."""
