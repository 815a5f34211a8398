"""A stand-in for the ROS package ``wecook`` of icaros-usc/wecook (only its ``msg`` module)."""
