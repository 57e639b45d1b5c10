"""Code emitted by ``chaplygin derive`` for the built-in models. DO NOT EDIT.

One numpy module, one mpmath module and one C source per model variant
(``<system>[__<effect>...]``); ``manifest.json`` maps each variant to its model hash and
files. ``chaplygin derive --check`` fails when any file here differs from a fresh
emission.
"""
