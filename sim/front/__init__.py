"""The front ends: the ``linkage`` command line and the local web app, both over :mod:`sim.service`."""
