"""The study report: one self-contained HTML file and a PDF rendered from it.

:func:`build_report` is what the workflow's report rule calls. Importing this package is
cheap; pandas, matplotlib, Jinja2 and WeasyPrint are imported only when a report is built.

``inputs`` maps a short name to a path (or, for the keys in :data:`LIST_INPUTS`, a list
of paths):

required
    ``weighted``, ``runs``
optional (a section whose input is absent says so instead of showing data)
    lab study: ``trace_stats``, ``reference_stats``, ``imu_errors``, ``per_test_errors``,
    ``rtf``, ``cpu``, ``qualitative``, ``table11``, ``table11_comparison``,
    ``worked_example``, ``endpoints`` (rule figure_paths' table of where each run ended)
    figures: ``figures``, the files the figure rules drew (:mod:`simpick.report.draw`; PNG, and
    the JSON notes some write beside them), embedded by name (:func:`simpick.report.load.figure_key`);
    a figure that is not given is not shown. ``traces`` is read by the figure jobs, not the report.
    accuracy: ``scores_provenance`` (the scores job's record of what the scores rest on:
    errors file, tests, exclusions and why; simpick.score.jobs.score_provenance),
    ``accuracy_errors`` (the Eq. 7 totals it names; lab imu_errors layout) and
    ``accuracy_per_test`` (the real-data per-test table beside them)
    real robot data (rules/real.smk): ``segments`` (the committed segment table) and
    ``segments_provenance``; ``segments_per_test``, ``segments_summary``,
    ``segments_pairwise``, ``segments_imu_errors``; with the full replay
    ``replay_per_window``, ``replay_per_test``, ``replay_summary``, ``replay_pairwise``,
    ``replay_imu_errors``, ``real_logs`` (canonical logs) and ``replay_traces``
    calibration (rules/calibration.smk): ``calibration`` (its summary.csv), ``calibration_turning`` and
    ``calibration_target`` (turning.csv, target.csv: held-out yaw-rate gains and the turning target)

``params``: ``weights`` (metric -> weight; the paper's defaults when absent), ``config``
(the slice of the study config the report reads: terrains, motions, robot track; shown under
provenance and used for test order, terrain strip and commanded paths), ``statistics``
(``min_runs``, ``level``: when the real-data section may give an interval or verdict), ``title`` (optional),
``real_data`` (``dataset`` and ``classes``: terrain class -> {friction, source}, how each class
was modelled). Which data the accuracy scores rest on comes from ``scores_provenance`` only.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from simpick.report.inputs import LIST_INPUTS, OPTIONAL_INPUTS, REQUIRED_INPUTS

__all__ = ["build_report", "REQUIRED_INPUTS", "OPTIONAL_INPUTS", "LIST_INPUTS"]


def build_report(
    inputs: Mapping[str, Any], params: Mapping[str, Any], html_path: str | Path, pdf_path: str | Path | None = None
) -> None:
    """Write the HTML report to ``html_path`` and, if ``pdf_path`` is given, the same document as PDF
    (one job: the PDF is laid out from the HTML just rendered, with no second process or read)."""
    import sys
    import time

    from simpick.report.build import render_html, write_pdf
    from simpick.report.load import load_inputs

    start = time.perf_counter()
    data = load_inputs(inputs)
    html = render_html(data, params)
    rendered = time.perf_counter()
    html_path = Path(html_path)
    html_path.parent.mkdir(parents=True, exist_ok=True)
    tmp = html_path.with_name(html_path.name + ".partial")
    tmp.write_text(html, encoding="utf-8")
    tmp.replace(html_path)
    print(f"report: HTML {rendered - start:.1f} s", file=sys.stderr)
    if pdf_path is not None:
        write_pdf(html, pdf_path, base_url=str(html_path.parent))
        print(f"report: PDF {time.perf_counter() - rendered:.1f} s", file=sys.stderr)
