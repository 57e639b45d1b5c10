"""Generic dynamics of any model: Poincaré maps (stroboscopic and by a section), variational
equations and Lyapunov spectra, periodic orbits of maps, their continuation, the batch map,
attractors and repellers of reversible maps.

No module here names a state variable or a parameter of a particular system: a model's
state, its groups, its forcing frequency (:attr:`~chaplygin.numerics.code.ModelCode.forcing`)
and its Poisson geometry come from the model (``tests/verify/test_layers.py`` checks).
"""
