"""The ``linkage/1`` file format: reading and checking a file (:mod:`.linkfile`) and the arithmetic of its
values (:mod:`.expr`). Data flows down from here: format -> topology -> solver -> applications."""
