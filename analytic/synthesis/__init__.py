"""Finding a linkage: seed 001's two-position method, path, motion and function synthesis."""
