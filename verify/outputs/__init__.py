"""Scene outputs: the analyses a scene runs by name (Poincaré maps, Lyapunov spectra, periodic
orbits), their scene tables, and what the trajectory outputs draw and write (the energy diagram,
the separatrix's Δ, the trajectory file).

Each module imports of the scene package only its public interface for outputs,
:mod:`chaplygin.verify.scene.outputs`; the scene finds the analyses by key through
:mod:`chaplygin.verify.scene.registry` (``tests/verify/test_layers.py`` checks both).
"""
