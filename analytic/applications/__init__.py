"""What is computed from a solved mechanism: figures of merit, drive forces, motion under a motor and
design studies."""
