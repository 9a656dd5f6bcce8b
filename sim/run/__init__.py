"""Running a model: the recorded simulation, its comparison with the analytic solution, the linkage
driven by a motor, and parallel execution."""
