"""Traces against their references: the paper's Eq. 7 errors, the real-data metrics and statistics, and the per-
source comparison and summary jobs.
"""
