"""Subcommands that run MuJoCo: simulate, compare, render, plot, run."""


def register(sub, add_common) -> None:
    pass
