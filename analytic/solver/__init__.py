"""The general solver: positions, velocities and accelerations of every point, link and prismatic pair,
one Assur group at a time (:mod:`.kinematics`), its compiled path (:mod:`.jit`), many designs at once
(:mod:`.batch`) and the numerically solved groups (:mod:`.general_group`)."""
