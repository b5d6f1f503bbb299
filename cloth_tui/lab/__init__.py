"""The virtual textile lab's expectations, computed (a Newton, bisection or ODE solve), not
typed in: the catenary, the self-weight cantilever (elastica), the Peirce / ASTM D1388
cantilever test and the hanging chain's swing. The tests that run the simulator against
them need rectangular sheets and pin groups, which are not built yet. Pure numpy."""
