"""Verification layer: claims, verdicts, reports and the command line (top layer)."""
