"""The ``linkage/1`` file format: reading and checking a file (:mod:`.linkfile`) and the arithmetic of its
values (:mod:`.expr`). Data flows down from here: format -> topology -> solver -> applications."""


def __getattr__(name: str):
    """PEP 562: a submodule on first access (``analytic.format.linkfile`` after a bare ``import analytic``,
    whose names are imported on first use)."""
    import importlib
    if name.startswith("__"):
        raise AttributeError(name)
    try:
        return importlib.import_module(f"{__name__}.{name}")
    except ModuleNotFoundError as exc:
        if exc.name != f"{__name__}.{name}":
            raise
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
