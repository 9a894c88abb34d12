"""From the context to the page and the PDF: the templates' environment, the report's HTML, the
evidence's fragment and page (sections 2-5 and the appendices), and WeasyPrint's PDF of an HTML document."""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from simpick.report import formats
from simpick.report.context import build_context, evidence_context
from simpick.report.load import ReportData

TEMPLATE_DIR = Path(__file__).resolve().parent / "templates"
TEMPLATE = "report.html.j2"
EVIDENCE_TEMPLATE = "evidence.html.j2"
EVIDENCE_PAGE = "evidence_page.html.j2"


def environment():
    import jinja2

    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(TEMPLATE_DIR)),
        autoescape=jinja2.select_autoescape(["html", "j2"]),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
    )
    env.filters.update(
        f3=formats.fmt,
        f=formats.fmt,
        num=formats.fmt_num,
        int=formats.fmt_int,
        signed=formats.fmt_signed,
        yesno=formats.fmt_yes_no,
        isnan=formats.isnan,
        soft_lower=formats.soft_lower,
        sig3=formats.fmt_sig,
    )
    env.tests["nan"] = formats.isnan
    return env


def render_html(data: ReportData, params: Mapping[str, Any], evidence: str | None = None) -> str:
    """The report's page; ``evidence``: the HTML placed after section 1 of the evidence (the fragment of
    :func:`render_evidence`: sections 2-5 and the appendices), rendered here from ``data`` when not
    given: the whole report."""
    from markupsafe import Markup

    if evidence is None:
        evidence = render_evidence(data, params)[0]
    ctx = build_context(data, params)
    return environment().get_template(TEMPLATE).render(**ctx, evidence=Markup(evidence))


def render_evidence(data: ReportData, params: Mapping[str, Any]) -> tuple[str, str]:
    """The evidence's sections 2-5 and the appendices: the HTML fragment the report places after its
    body, and the same fragment as a document of its own (the report's style), for their PDF."""
    from markupsafe import Markup

    env = environment()
    ctx = evidence_context(data, params)
    fragment = env.get_template(EVIDENCE_TEMPLATE).render(**ctx)
    page = env.get_template(EVIDENCE_PAGE).render(title=ctx["title"], fragment=Markup(fragment))
    return fragment, page


def anchor_ids(html: str) -> list[str]:
    """Every ``id`` an HTML fragment defines, in order."""
    return list(dict.fromkeys(re.findall(r"""\bid=["']([^"']+)["']""", html)))


def write_pdf(html: str, pdf_path: str | Path, base_url: str | None = None, footers: bool = True) -> None:
    """The PDF of ``html``. ``footers`` False: without the page's footer (the report's name and
    "page n of N"), for a part that :func:`simpick.report.pdf.join` puts in one document and numbers."""
    import logging

    import weasyprint

    # WeasyPrint logs each CSS property it ignores; the report's CSS is written for it.
    logging.getLogger("weasyprint").setLevel(logging.ERROR)
    pdf_path = Path(pdf_path)
    pdf_path.parent.mkdir(parents=True, exist_ok=True)
    tmp = pdf_path.with_name(pdf_path.name + ".partial")
    sheets = [] if footers else [weasyprint.CSS(string=NO_FOOTERS)]
    weasyprint.HTML(string=html, base_url=base_url).write_pdf(str(tmp), stylesheets=sheets)
    tmp.replace(pdf_path)


# !important: a user stylesheet's declaration wins over the document's (author) own only so
NO_FOOTERS = "@page { @bottom-left { content: none !important } @bottom-right { content: none !important } }"
