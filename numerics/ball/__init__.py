"""The rolling ball's own studies: initial states by integrals and the frame rule, the
separatrix and its displacement Δ, the contact point's trace and the frame turn, quadratures
and rotation numbers, Floquet multipliers of the papers' families, the bifurcation and
energy diagrams, Chaplygin's transformation, Andoyer-Deprit map coordinates, the symmetric
copies of attractors and the regimes of BM20's map.

These name the ball's state (``M``, ``gamma``, ``alpha``, ``beta``) and its parameters; the
generic machinery they use lives in :mod:`chaplygin.numerics.dynamics` and the engine.
"""
