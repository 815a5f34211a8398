"""Scheduling a plan's actions over two arms: the executor, the program each action runs, the run's observer."""
