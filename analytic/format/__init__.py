"""The ``linkage/1`` file format: reading and checking a file (:mod:`.linkfile`) and the arithmetic of its
values (:mod:`.expr`). Data flows down from here: format -> topology -> solver -> applications."""


import lazy_loader

# a submodule on first access (``analytic.format.linkfile`` after a bare ``import analytic``)
__getattr__, __dir__, __all__ = lazy_loader.attach(__name__, submodules=(
    "expr", "foreign", "joints", "lawfield", "linkfile", "parts_table", "pmks", "pyslvs", "sym", "writing"))
