"""The virtual textile lab's expectations, computed (a Newton, bisection or ODE solve), not
typed in: the catenary, the self-weight cantilever (elastica), the Peirce / ASTM D1388
cantilever test and the hanging chain's swing. The tests that run the simulator against
them need pin groups, which are not built yet (rectangular sheets are). Plain Python
(`math`): no numpy or scipy needed."""
