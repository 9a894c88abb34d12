"""One report.pdf from its parts (pypdf): the body's PDF, which the weights reach, and the evidence's
(sections 2-5 and the appendices), which no weight reaches and a job of its own renders (rule
report_evidence), so that a weight edit lays out the body alone.

Each part is rendered without the page footer (:data:`simpick.report.render.NO_FOOTERS`): :func:`join`
puts the parts' pages in one document, one after the other, and draws on every page the footer the
report's CSS gives (the report's name, "page n of N"), laid out by WeasyPrint on blank pages of the
joined document's count and placed on each page as a form. The links between the parts keep working:
WeasyPrint links to a named destination (the element's id), and the body is rendered with an empty
element of every id the evidence defines (:func:`placeholders`), whose destinations the join replaces
by the evidence's own. The outline (bookmarks) is the one a single pass would give: the body's, and the
later parts' entries under the body's last top-level entry (the report's title, the only one).
"""

from __future__ import annotations

import html as _html
import io
from collections.abc import Iterable, Sequence
from pathlib import Path

FOOTER_FORM = "/SimpickFooter"


def placeholders(ids: Iterable[str]) -> str:
    """Empty blocks bearing ``ids`` (the evidence's anchors), placed after the body in the document
    the body's PDF is rendered from: WeasyPrint keeps a link only when its anchor is in the document,
    and :func:`join` points each of these names at the evidence's element."""
    return "".join(f'<div id="{_html.escape(i, quote=True)}"></div>' for i in ids)


def footer_sheet(n_pages: int, cache: str | Path | None = None) -> bytes:
    """``n_pages`` blank pages with the report's footers ("page n of N"), as a PDF (WeasyPrint,
    the report's own CSS: same page size, margins, font). With ``cache``, a folder: the sheet is kept there
    under a name that hashes the page count, the CSS and WeasyPrint's version, and read back when one of that
    name is there: a weight edit leaves the page count as it was, and laying out the sheet again took about
    0.26 s of the report job for 60 pages on this machine."""
    import hashlib
    import logging

    import weasyprint

    from simpick.report.render import environment

    css = environment().get_template("report.css").render()
    kept = None
    if cache is not None:
        key = hashlib.sha256(f"{n_pages}\n{weasyprint.__version__}\n{css}".encode()).hexdigest()[:32]
        kept = Path(cache) / f"footers-{key}.pdf"
        if kept.is_file():
            return kept.read_bytes()
    logging.getLogger("weasyprint").setLevel(logging.ERROR)
    pages = '<div class="pagebreak"></div>' * n_pages
    document = f"<!DOCTYPE html><html><head><style>{css}</style></head><body>{pages}</body></html>"
    sheet = weasyprint.HTML(string=document).write_pdf()
    if kept is not None:
        try:  # a cache that cannot be written costs time, never a result
            kept.parent.mkdir(parents=True, exist_ok=True)
            tmp = kept.with_name(f"{kept.name}.{id(sheet)}.partial")
            tmp.write_bytes(sheet)
            tmp.replace(kept)
        except OSError:
            pass
    return sheet


def _name_pairs(tree) -> list:
    """The (name, value) pairs of a PDF name tree (a /Names array, or /Kids)."""
    tree = tree.get_object()
    pairs = tree.get("/Names") or []
    out = [(pairs[i], pairs[i + 1]) for i in range(0, len(pairs) - 1, 2)]
    for kid in tree.get("/Kids") or []:
        out += _name_pairs(kid)
    return out


def _repoint(writer, readers, offsets) -> None:
    """Where two parts name the same destination, point the joined document's name at the later
    part's (pypdf's append keeps the first), so that the body's placeholders yield to the evidence's
    anchors; the links, which name their destination, follow."""
    from pypdf.generic import ArrayObject, DictionaryObject, FloatObject, NameObject, NullObject, TextStringObject

    later = {}
    for reader, offset in zip(readers[1:], offsets[1:]):
        for name, dest in reader.named_destinations.items():
            page = writer.pages[offset + reader.get_destination_page_number(dest)].indirect_reference
            coords = [FloatObject(v) if v is not None else NullObject() for v in (dest.left, dest.top, dest.zoom)]
            later[name] = ArrayObject([page, NameObject("/XYZ"), *coords])
    if not later:
        return
    names = writer.root_object.get("/Names")
    dests = names.get_object().get("/Dests") if names is not None else None
    pairs = {str(k): v for k, v in _name_pairs(dests)} if dests is not None else {}
    pairs.update(later)
    flat = ArrayObject()
    for name in sorted(pairs):
        flat += [TextStringObject(name), pairs[name]]
    if names is None:
        writer.root_object[NameObject("/Names")] = DictionaryObject()
        names = writer.root_object["/Names"]
    names.get_object()[NameObject("/Dests")] = writer._add_object(DictionaryObject({NameObject("/Names"): flat}))


def _copy_outline(writer, reader, items, offset: int, parent=None) -> list:
    """Add ``items`` (a part's outline: entries, each followed by the list of its children, if any)
    to ``writer`` under ``parent``, each pointing where it pointed, ``offset`` pages on. Returns the
    entries added at this level."""
    from pypdf.generic import Fit

    added = []
    for item in items:
        if isinstance(item, list):
            _copy_outline(writer, reader, item, offset, added[-1] if added else parent)
            continue
        fit = Fit.xyz(item.left, item.top, item.zoom) if item.typ == "/XYZ" else Fit.fit()
        page = offset + reader.get_destination_page_number(item)
        added.append(writer.add_outline_item(title=item.title, page_number=page, parent=parent, fit=fit))
    return added


def _stamp(page, footer, writer) -> None:
    """Draw the footer page ``footer`` (of the footer sheet) on ``page``, as a form XObject, after
    the page's own content (wrapped in q/Q so that its graphics state does not reach the footer)."""
    from pypdf.generic import (
        ArrayObject,
        DecodedStreamObject,
        DictionaryObject,
        FloatObject,
        NameObject,
    )

    form = DecodedStreamObject()
    form.set_data(footer.get_contents().get_data())
    form.update(
        {
            NameObject("/Type"): NameObject("/XObject"),
            NameObject("/Subtype"): NameObject("/Form"),
            NameObject("/BBox"): ArrayObject(FloatObject(x) for x in footer.mediabox),
            NameObject("/Resources"): footer["/Resources"].get_object().clone(writer),
        }
    )
    form_ref = writer._add_object(form)
    # the page's own resources (WeasyPrint shares one dictionary between pages): a shallow copy
    # with the footer's form added
    resources = page.get("/Resources")
    resources = DictionaryObject() if resources is None else DictionaryObject(resources.get_object())
    xobjects = resources.get("/XObject")
    xobjects = DictionaryObject() if xobjects is None else DictionaryObject(xobjects.get_object())
    xobjects[NameObject(FOOTER_FORM)] = form_ref
    resources[NameObject("/XObject")] = xobjects
    page[NameObject("/Resources")] = resources

    def stream(data: bytes):
        s = DecodedStreamObject()
        s.set_data(data)
        return writer._add_object(s)

    contents = page.get("/Contents")
    contents = contents.get_object() if contents is not None else ArrayObject()
    parts = list(contents) if isinstance(contents, ArrayObject) else [page.raw_get("/Contents")]
    page[NameObject("/Contents")] = ArrayObject(
        [stream(b"q\n"), *parts, stream(b"\nQ\nq " + FOOTER_FORM.encode() + b" Do Q\n")]
    )


def join(
    parts: Sequence[str | Path], out: str | Path, footers: bytes | None = None, footer_cache: str | Path | None = None
) -> int:
    """Write the PDFs ``parts`` (the body first) as one document ``out``, every page with its footer
    (``footers``: a footer sheet of the joined page count; made here when not given, kept in ``footer_cache``
    when that names a folder: :func:`footer_sheet`); where two parts
    name the same destination, the later part's wins (the body's placeholders yield to the
    evidence's anchors); the later parts' bookmarks go under the body's last top-level one, as in a
    document laid out in one pass. Returns the page count."""
    from pypdf import PdfReader, PdfWriter

    readers = [PdfReader(str(p)) for p in parts]
    writer = PdfWriter()
    offsets = []
    for reader in readers:
        offsets.append(len(writer.pages))
        writer.append(reader, import_outline=False)
    _repoint(writer, readers, offsets)
    top = _copy_outline(writer, readers[0], readers[0].outline, 0) if readers else []
    for reader, offset in zip(readers[1:], offsets[1:]):
        _copy_outline(writer, reader, reader.outline, offset, top[-1] if top else None)
    if readers and readers[0].metadata:
        writer.add_metadata({k: v for k, v in readers[0].metadata.items() if isinstance(k, str)})
    n = len(writer.pages)
    sheet = PdfReader(io.BytesIO(footers if footers is not None else footer_sheet(n, footer_cache)))
    if len(sheet.pages) != n:
        raise ValueError(f"footer sheet has {len(sheet.pages)} pages, the joined document {n}")
    for page, footer in zip(writer.pages, sheet.pages):
        _stamp(page, footer, writer)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_name(out.name + ".partial")
    with open(tmp, "wb") as fh:
        writer.write(fh)
    tmp.replace(out)
    return n
