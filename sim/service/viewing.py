"""What a live view of a mechanism shows besides its curves (the app's figures card; public API)."""

from __future__ import annotations


def figures_summary(mech, figures: dict) -> list[str]:
    """The figures of merit of :func:`sim.service.analyze` as the short lines a view shows under its curves
    (the same lines ``linkage analyze`` prints)."""
    from analytic.applications.figures import summary
    return summary(mech, figures)
