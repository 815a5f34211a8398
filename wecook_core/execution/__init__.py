"""Execution of a plan by two arms in PyBullet (headless), recorded through a RunObserver."""
