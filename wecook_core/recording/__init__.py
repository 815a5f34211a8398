"""Recording a run: MCAP writer, Foxglove schemas and layout, live view, meshes, camera, check, recovery, report."""
