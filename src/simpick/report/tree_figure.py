"""The decision tree (results/verdict/tree.json) drawn for print: questions left to right, the answers
on the edges, the leaves in a column on the right, each a letter (:func:`leaf_letters`) and its engines
in the tree's order. No weight reaches the figure, so a weight edit does not redraw it (Matplotlib's
import and drawing are off the weight-edit path): the report orders each leaf's engines by the paper's
weighted total in a table under the figure (:func:`leaf_rows`), from the weighted table it reads."""

from __future__ import annotations

import textwrap

from simpick.score.tree import leaf_order, read_tree

ROW = 0.34  # inches a leaf takes
FONT = 6.5  # points: readable at A4 width (the figure is drawn at its printed size)
WIDTH = 7.3  # inches: the A4 text width


def layout(tree: dict) -> tuple[dict[str, tuple[int, float]], list[str], int]:
    """Depth and vertical slot of every node (leaves on consecutive slots from the top, a question
    midway between its first and last child); the leaves in order; the deepest question's depth."""
    place: dict[str, tuple[int, float]] = {}
    leaves: list[str] = []

    def visit(nid: str, depth: int) -> float:
        node = tree["nodes"][nid]
        if node["kind"] == "leaf":
            leaves.append(nid)
            place[nid] = (depth, float(len(leaves) - 1))
            return place[nid][1]
        children = list(dict.fromkeys(a["next"] for a in node["answers"]))
        slots = [visit(c, depth + 1) for c in children]
        place[nid] = (depth, (slots[0] + slots[-1]) / 2)
        return place[nid][1]

    visit(tree["root"], 0)
    depth = max((d for n, (d, _) in place.items() if tree["nodes"][n]["kind"] == "question"), default=0)
    return place, leaves, depth


def leaf_letters(tree: dict) -> dict[str, str]:
    """Leaf id -> the letter the figure prints beside it (A, B, ... top to bottom; AA, AB, ... past Z),
    by which the report's table of the leaves names them."""
    _, leaves, _ = layout(tree)

    def letter(i: int) -> str:
        return chr(65 + i) if i < 26 else letter(i // 26 - 1) + chr(65 + i % 26)

    return {nid: letter(i) for i, nid in enumerate(leaves)}


def leaf_rows(tree: dict, totals: dict[str, float]) -> list[dict]:
    """The report's table under the figure: per leaf (in the figure's order) its letter, its pick and the
    others by the paper's weighted total (``totals``: engine -> total; :func:`simpick.score.tree.leaf_order`),
    each engine with its total (None where it has none) and whether it fails analytic mechanics."""
    fails = _mechanics_fails(tree)
    rows = []
    for nid, letter in leaf_letters(tree).items():
        engines = leaf_order(tree["nodes"][nid]["engines"], totals)
        rows.append(
            {
                "letter": letter,
                "engines": [
                    {"engine": e, "total": totals.get(e), "fails": e in fails, "pick": i == 0}
                    for i, e in enumerate(engines)
                ],
            }
        )
    return rows


def _mechanics_fails(tree: dict) -> set[str]:
    mechanics = next((q for q in tree["questions"] if q["key"] == "mechanics"), None)
    return {e for e, f in (mechanics or {"facts": {}})["facts"].items() if f["value"] is False}


def draw_tree(tree: dict):
    """The figure (matplotlib) of ``tree``: each leaf's letter and its engines in the tree's order."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    place, leaves, depth = layout(tree)
    fails = _mechanics_fails(tree)
    letters = leaf_letters(tree)
    leaf_width = 2.0
    column = (WIDTH - leaf_width - 0.1) / (depth + 1)
    height = ROW * max(len(leaves), 3) + 0.75
    fig = plt.figure(figsize=(WIDTH, height))
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(0, WIDTH)
    ax.set_ylim(height, 0)
    ax.axis("off")
    top = 0.35

    def xy(nid: str) -> tuple[float, float]:
        d, slot = place[nid]
        node = tree["nodes"][nid]
        x = WIDTH - leaf_width if node["kind"] == "leaf" else 0.05 + d * column
        return x, top + (slot + 0.5) * ROW

    chars = 72 / (FONT * 0.52)  # characters an inch holds at the font size
    wrap = max(10, int(0.6 * column * chars))
    for nid, node in tree["nodes"].items():
        if node["kind"] != "question":
            continue
        x, y = xy(nid)
        ax.text(
            x,
            y,
            textwrap.fill(node["text"], wrap),
            fontsize=FONT,
            va="center",
            ha="left",
            bbox={"boxstyle": "round,pad=0.25", "fc": "#eef3fb", "ec": "#5577aa", "lw": 0.6},
        )
        labels: dict[str, list[str]] = {}
        full: dict[str, list[str]] = {}
        for answer in node["answers"]:
            labels.setdefault(answer["next"], []).append(answer.get("short") or answer["label"])
            full.setdefault(answer["next"], []).append(answer["label"])
        for child, names in full.items():  # several kinds of yes that keep the same engines: one "Yes"
            if len(names) > 1 and all(n.startswith("Yes") for n in names):
                labels[child] = ["Yes"]
        elbow = x + 0.66 * column
        for child, names in labels.items():
            cx, cy = xy(child)
            ax.plot([elbow - 0.05, elbow, cx - 0.04], [y, cy, cy], color="#888888", lw=0.5)
            ax.text(
                elbow + 0.03,
                cy - 0.02,
                textwrap.fill(" / ".join(names), int((cx - elbow) * chars * 1.1)),
                fontsize=FONT - 1,
                va="bottom",
                ha="left",
                color="#333333",
            )
    for nid in leaves:
        node = tree["nodes"][nid]
        x, y = xy(nid)
        ax.text(x, y, letters[nid], fontsize=FONT + 0.5, va="center", fontweight="bold")
        if not node["engines"]:
            ax.text(x + 0.22, y, "no engine meets these answers", fontsize=FONT, va="center", color="#b03000")
            continue
        names = ", ".join(f"{e}{'†' if e in fails else ''}" for e in node["engines"])
        ax.text(
            x + 0.22,
            y,
            textwrap.fill(names, int((leaf_width - 0.22) * chars * 1.1), max_lines=2, placeholder="..."),
            fontsize=FONT - 0.5,
            va="center",
        )
    ax.text(
        0.05,
        0.15,
        "Decision tree from the study's evidence: each answer keeps the engines that meet it",
        fontsize=FONT + 1.5,
        fontweight="bold",
        va="center",
    )
    legend = (
        "Leaves: a letter and the engines that meet every answer, in the study's order (the table under the "
        "figure orders each leaf by the paper's weighted total at the study's weights)"
        + ("; † fails analytic mechanics" if fails else "")
    )
    if tree.get("not_asked"):
        legend += ". Not asked (no answer changes the engines): " + "; ".join(
            f"{q['question']} ({q['why']})" for q in tree["not_asked"]
        )
    ax.text(0.05, height - 0.12, textwrap.fill(legend, 150), fontsize=FONT - 1, va="bottom", color="#333333")
    return fig


def tree_figure_job(tree_path: str, output: str) -> None:
    """Rule figure_tree: results/report/figures/tree.png, from the tree alone (no weight)."""
    from pathlib import Path

    fig = draw_tree(read_tree(tree_path))
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(output, dpi=200)
