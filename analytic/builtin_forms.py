"""The three built-ins' closed-form modules and their classes by name, as the package gives them
(``analytic.fourbar``, ``analytic.FourBar``, ``analytic.MECHANISMS``)."""

from analytic.closed_forms import fivebar, fourbar, sixbar

FourBar, SixBar, FiveBar = fourbar.FourBar, sixbar.SixBar, fivebar.FiveBar
MECHANISMS = {"fourbar": fourbar, "sixbar": sixbar, "fivebar": fivebar}
