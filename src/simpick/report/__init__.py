"""The study report: one self-contained HTML file and a PDF rendered from it.

:func:`build_report` is what the workflow's report rule calls. Importing this package is
cheap; pandas, matplotlib, Jinja2 and WeasyPrint are imported only when a report is built.

``inputs`` maps a short name to a path (or, for ``cpu`` and ``traces``, a list of paths):

required
    ``weighted``, ``runs``
optional (a section whose input is absent says so instead of showing data)
    ``trace_stats``, ``reference_stats``, ``imu_errors``, ``per_test_errors``, ``rtf``,
    ``cpu``, ``qualitative``, ``table11``, ``table11_comparison``, ``worked_example``,
    ``traces``

``params``: ``weights`` (metric -> weight; the paper's defaults when absent), ``config``
(the canonical study config, shown under provenance and used for test order, terrain strip
and commanded paths), ``title`` (optional).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

REQUIRED_INPUTS: tuple[str, ...] = ("weighted", "runs")
OPTIONAL_INPUTS: tuple[str, ...] = (
    "trace_stats",
    "reference_stats",
    "imu_errors",
    "per_test_errors",
    "rtf",
    "cpu",
    "qualitative",
    "table11",
    "table11_comparison",
    "worked_example",
    "traces",
)

__all__ = ["build_report", "REQUIRED_INPUTS", "OPTIONAL_INPUTS"]


def build_report(inputs: Mapping[str, Any], params: Mapping[str, Any],
                 html_path: str | Path, pdf_path: str | Path) -> None:
    """Write the HTML report to ``html_path`` and the same document as PDF to ``pdf_path``."""
    from simpick.report.build import render_html, write_pdf
    from simpick.report.load import load_inputs

    data = load_inputs(inputs)
    html = render_html(data, params)
    html_path = Path(html_path)
    html_path.parent.mkdir(parents=True, exist_ok=True)
    tmp = html_path.with_name(html_path.name + ".partial")
    tmp.write_text(html, encoding="utf-8")
    tmp.replace(html_path)
    write_pdf(html, pdf_path, base_url=str(html_path.parent))
