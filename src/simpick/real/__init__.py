"""Real robot data in: dataset folders, their import to the canonical log form, constant-command segments and the
real robot's turning.
"""
