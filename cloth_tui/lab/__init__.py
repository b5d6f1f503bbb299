"""The virtual textile lab (`cloth-tui lab`). Its expectations are computed (a Newton,
bisection or ODE solve), not typed in: the catenary, the self-weight cantilever (elastica),
the Peirce / ASTM D1388 cantilever test and the hanging chain's swing, in plain Python.
Its tests (hanging.py, ...) run the simulator on rectangular sheets held by pin groups
against them; study.py runs a test over resolutions, cli.py prints and plots it."""
