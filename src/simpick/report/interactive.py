"""The report's interactive part: the decision tree to answer (results/verdict/tree.json) and the
paper's weighted table with adjustable weights (the scores of results/scores/weighted.csv),
recomputed in the browser by the formula of :func:`simpick.score.scoring.weighted_table`.

:func:`choose_fragment` returns one self-contained HTML fragment (its style, data and script
inline: no network, no server) for the report to place in its page; :func:`choose_page` wraps it
in a page of its own. The fragment hides itself in print, where the static figure of the tree
(results/report/figures/tree.png) stands for it.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path

import pandas as pd

from simpick.errors import InputError
from simpick.score.scoring import METRIC_LABELS, METRICS

TEMPLATES = Path(__file__).parent / "templates" / "interactive"


def _json_for_script(value) -> str:
    """JSON safe inside <script>: no "<" at all (no "</script>" or "<!--" can end or bend the
    element; JSON reads the escape back as "<"), no NaN (JSON has none)."""
    return json.dumps(value, allow_nan=False, separators=(",", ":")).replace("<", "\\u003c")


def choose_data(tree: Mapping, weighted: pd.DataFrame, weights: Mapping[str, float], noun: str = "engine") -> dict:
    """What the page's script reads: the tree, the criteria, the study's weights, each engine's
    scores (None where not measured) and the flag of every engine that fails mechanics (the
    tree's mechanics question), shown beside its rank by the paper's method."""
    frame = weighted.set_index("engine") if "engine" in weighted.columns else weighted
    missing = [m for m in METRICS if m not in frame.columns]
    if missing:
        raise InputError(
            "results/scores/weighted.csv", f"lacks the score column(s) {', '.join(missing)}", "rerun rule weighted"
        )
    absent = [m for m in METRICS if m not in weights]
    if absent:
        raise InputError("config.yaml: weights", f"no weight for {', '.join(absent)}", "give every criterion a weight")
    tree_engines = list(tree["engines"])
    engines = [e for e in tree_engines if e in frame.index] + [e for e in frame.index if e not in tree_engines]

    def score(value) -> float | None:
        value = float(value)
        return value if math.isfinite(value) else None

    mechanics = next((q for q in tree["questions"] if q["key"] == "mechanics"), None)
    flags = {e: f["text"] for e, f in (mechanics or {"facts": {}})["facts"].items() if f["value"] is False}
    return {
        "tree": tree,
        "metrics": [{"key": m, "label": METRIC_LABELS[m]} for m in METRICS],
        "weights": {m: float(weights[m]) for m in METRICS},
        "engines": engines,
        "scores": {e: {m: score(frame.loc[e, m]) for m in METRICS} for e in engines},
        "flags": flags,
        "noun": noun,
    }


def choose_fragment(
    tree: Mapping,
    weighted: pd.DataFrame,
    weights: Mapping[str, float],
    noun: str = "engine",
    weighted_file: str = "results/scores/weighted.csv",
) -> str:
    """The interactive section as one HTML fragment (a <section> with its <style> and <script>).

    ``tree``: the parsed results/verdict/tree.json (:func:`simpick.score.tree.read_tree`);
    ``weighted``: results/scores/weighted.csv as read by pandas (an ``engine`` column or index);
    ``weights``: the study's weights (config.yaml ``weights:``), the inputs' starting values; ``noun``: what a
    leaf names ("engine", or "simulator" for results/simulators/tree.json), ``weighted_file`` where its scores are."""
    import jinja2

    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(TEMPLATES)), autoescape=True, undefined=jinja2.StrictUndefined
    )
    return env.get_template("choose.html.j2").render(
        css=(TEMPLATES / "choose.css").read_text(),
        js=(TEMPLATES / "choose.js").read_text(),
        data=_json_for_script(choose_data(tree, weighted, weights, noun)),
        noun=noun,
        weighted_file=weighted_file,
    )


def choose_page(
    tree: Mapping, weighted: pd.DataFrame, weights: Mapping[str, float], title: str = "simpick: pick an engine"
) -> str:
    """:func:`choose_fragment` in a page of its own."""
    from html import escape

    return (
        f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>{escape(title)}</title></head>\n'
        f"<body>\n{choose_fragment(tree, weighted, weights)}\n</body></html>\n"
    )
