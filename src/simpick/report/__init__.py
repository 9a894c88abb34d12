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

# where the report job keeps the PDF's footer sheets between runs (simpick.report.pdf.footer_sheet)
FOOTER_CACHE = ".snakemake/simpick/footers"

__all__ = ["build_report", "build_evidence", "report_job", "REQUIRED_INPUTS", "OPTIONAL_INPUTS", "LIST_INPUTS"]


def build_report(
    inputs: Mapping[str, Any],
    params: Mapping[str, Any],
    html_path: str | Path,
    pdf_path: str | Path | None = None,
    evidence_html: str | Path | None = None,
    evidence_pdf: str | Path | None = None,
    footer_cache: str | Path | None = None,
    workers: int = 1,
    worker=None,
) -> None:
    """Write the HTML report to ``html_path`` and, if ``pdf_path`` is given, the same document as PDF
    (one job: the PDF is laid out from the HTML just rendered, with no second process or read).

    With the evidence's sections 2-5 and the appendices rendered by :func:`build_evidence`
    (``evidence_html``, the fragment, and ``evidence_pdf``), the page places the fragment after
    section 1 of the evidence, and the PDF is the body's, laid out alone, joined with the evidence's
    (:func:`simpick.report.pdf.join`): one document, one page count, links and bookmarks across both; its
    page footers kept in ``footer_cache`` where that names a folder (:func:`simpick.report.pdf.footer_sheet`).
    The body's PDF is laid out in two parts (:func:`simpick.report.pdf.split_body`), ``workers`` at once, the
    second by ``worker`` where given (:class:`simpick.report.layout.LayoutWorker`, started with the job).
    Without them the evidence is rendered here from the same inputs and the PDF laid out in one pass
    (one job does all: tests, a report by hand)."""
    import sys
    import time

    from simpick.report.load import load_inputs
    from simpick.report.render import render_evidence, render_html, write_pdf

    start = time.perf_counter()
    data = load_inputs(inputs)
    if evidence_html:
        fragment = Path(evidence_html).read_text(encoding="utf-8")
    else:
        fragment, evidence_pdf = render_evidence(data, params)[0], None
    mark = "<!--simpick:evidence-->"
    page = render_html(data, params, evidence=mark)
    html = page.replace(mark, fragment, 1)
    rendered = time.perf_counter()
    html_path = Path(html_path)
    _write_text(html_path, html)
    print(f"report: HTML {rendered - start:.1f} s", file=sys.stderr)
    if pdf_path is None:
        return
    if not evidence_pdf:
        write_pdf(html, pdf_path, base_url=str(html_path.parent))
        print(f"report: PDF {time.perf_counter() - rendered:.1f} s", file=sys.stderr)
        return
    from simpick.report import pdf
    from simpick.report.render import anchor_ids

    evidence_ids = anchor_ids(fragment)
    parts = pdf.split_body(page, mark, evidence_ids)
    paths = [Path(pdf_path).with_name(f"{Path(pdf_path).name}.body{i}") for i in range(len(parts))]
    try:
        _lay_out([document for document, _ in parts], paths, str(html_path.parent), workers, worker)
        laid_out = time.perf_counter()
        owners = [ids for _, ids in parts] + [set(evidence_ids)]
        n = pdf.join([*paths, evidence_pdf], pdf_path, footer_cache=footer_cache, owners=owners)
    finally:
        for path in paths:
            path.unlink(missing_ok=True)
    print(
        f"report: PDF {time.perf_counter() - rendered:.1f} s (body in {len(parts)} part(s), "
        f"{min(workers, len(parts))} at once, {laid_out - rendered:.1f} s, joined with the evidence and numbered "
        f"{time.perf_counter() - laid_out:.1f} s; {n} pages)",
        file=sys.stderr,
    )


def _lay_out(documents: list[str], paths: list[Path], base_url: str, workers: int, worker=None) -> None:
    """WeasyPrint's PDF of each document (the body's parts, no footers), ``workers`` at once: the second by
    ``worker`` (a process started with the job, WeasyPrint imported meanwhile) or by a process forked now,
    the first here."""
    from simpick.report.render import write_pdf

    if workers < 2 or len(documents) < 2:
        for document, path in zip(documents, paths):
            write_pdf(document, path, base_url=base_url, footers=False)
        return
    own = worker is None  # a worker forked here, else the job's, which it closes itself
    if own:
        from simpick.report.layout import LayoutWorker

        worker = LayoutWorker()
    try:
        (second, *rest), (second_path, *rest_paths) = documents[1:], paths[1:]
        worker.submit(second, second_path, base_url)
        for document, path in [(documents[0], paths[0]), *zip(rest, rest_paths)]:
            write_pdf(document, path, base_url=base_url, footers=False)
        worker.wait()
    finally:
        if own:
            worker.close()


def build_evidence(
    inputs: Mapping[str, Any], params: Mapping[str, Any], html_path: str | Path, pdf_path: str | Path
) -> None:
    """The evidence's sections 2-5 and the appendices, which no weight reaches: ``html_path`` the HTML
    fragment the report places after section 1 of the evidence, ``pdf_path`` their PDF, without page
    footers (the report numbers the joined document). ``inputs`` as the report's less the weighted
    tables, plus ``scores`` (the scores job's per-metric scores, results/scores/scores.csv: shown beside
    the figures; none when not given)."""
    import dataclasses
    import sys
    import time

    import pandas as pd

    from simpick.report.load import load_inputs
    from simpick.report.render import render_evidence, write_pdf

    start = time.perf_counter()
    inputs = dict(inputs)
    scores = inputs.pop("scores", None)
    data = load_inputs({k: v for k, v in inputs.items() if k != "weighted"}, required=("runs",))
    table = pd.read_csv(scores, index_col="engine") if scores else pd.DataFrame(index=pd.Index([], name="engine"))
    data = dataclasses.replace(
        data, weighted=table, sources={**data.sources, **({"scores": str(scores)} if scores else {})}
    )
    fragment, document = render_evidence(data, params)
    rendered = time.perf_counter()
    _write_text(Path(html_path), fragment)
    print(f"evidence: HTML {rendered - start:.1f} s", file=sys.stderr)
    write_pdf(document, pdf_path, base_url=str(Path(html_path).parent), footers=False)
    print(f"evidence: PDF {time.perf_counter() - rendered:.1f} s", file=sys.stderr)


def _write_text(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".partial")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(path)


def report_job(
    inputs: Mapping, weighing: Mapping, settings: Mapping, outputs: Mapping[str, str], lists=(), workers: int = 1
) -> None:
    """Rule report: the weighing (:func:`simpick.report.weighing.weigh`) into the job's outputs, then the page
    and its PDF (:func:`build_report`) from the job's other inputs and the weighed tables. ``settings``:
    the plan's report params with the folders the rule takes from its inputs; ``lists``: the input names
    that are lists of files; ``workers``: the processes that lay out the PDF's body (the job's threads)."""
    worker = None
    if workers > 1:  # forked first, so that it imports WeasyPrint while this process weighs and writes the HTML
        from simpick.report.layout import LayoutWorker

        worker = LayoutWorker()
    try:
        _report(inputs, weighing, settings, outputs, lists, workers, worker)
    finally:
        if worker is not None:
            worker.close()


def _report(inputs, weighing, settings, outputs, lists, workers, worker) -> None:
    from simpick.report.weighing import PREFIX, weigh

    weighed = weigh(inputs, weighing, outputs)
    evidence = ("evidence_html", "evidence_pdf")  # rule report_evidence's files, placed by build_report
    page_inputs = {
        key: (list(value) if key in lists else value)
        for key, value in inputs.items()
        if key not in evidence and not key.startswith(PREFIX)
    } | weighed
    build_report(
        page_inputs,
        settings,
        outputs["html"],
        outputs["pdf"],
        evidence_html=inputs["evidence_html"],
        evidence_pdf=inputs["evidence_pdf"],
        # beside the code versions' cache of the working directory's Snakemake folder (simpick.codeversion)
        footer_cache=FOOTER_CACHE,
        workers=workers,
        worker=worker,
    )
