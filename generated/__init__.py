"""Code emitted by ``chaplygin derive`` for the built-in models. DO NOT EDIT.

Per model variant (``<system>[__<effect>...]``) the files of every emitter of
``chaplygin.derive.emit``: numpy, mpmath and C modules, the Taylor recurrences in Python, C and
C on MPFR, the Taylor program as data and the right-hand side in vector lanes;
``manifest.json`` maps each variant to its model hash and files. ``chaplygin derive
--check`` fails when any file here differs from a fresh emission.
"""
