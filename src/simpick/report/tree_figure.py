"""The decision tree (results/verdict/tree.json) drawn for print: questions left to right, the answers
on the edges, the leaves in a column on the right, each leaf's engines ordered by the paper's
weighted total at the study's weights (results/scores/weighted.csv), the pick first."""

from __future__ import annotations

import textwrap

import pandas as pd

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


def draw_tree(tree: dict, totals: dict[str, float]):
    """The figure (matplotlib) of ``tree`` with leaves ordered by ``totals``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    place, leaves, depth = layout(tree)
    mechanics = next((q for q in tree["questions"] if q["key"] == "mechanics"), None)
    fails = {e for e, f in (mechanics or {"facts": {}})["facts"].items() if f["value"] is False}
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
        if not node["engines"]:
            ax.text(x, y, "no engine meets these answers", fontsize=FONT, va="center", color="#b03000")
            continue
        ordered = leaf_order(node["engines"], totals)

        def name(e: str) -> str:
            total = totals.get(e)
            return f"{e}{'†' if e in fails else ''} {total:.1f}" if total is not None else e

        ax.text(x, y - 0.045, name(ordered[0]), fontsize=FONT + 0.5, va="center", fontweight="bold")
        if len(ordered) > 1:
            rest = "then " + ", ".join(name(e) for e in ordered[1:])
            ax.text(
                x,
                y + 0.085,
                textwrap.shorten(rest, int(leaf_width * chars), placeholder="..."),
                fontsize=FONT - 1,
                va="center",
                color="#333333",
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
        "Leaves: the pick in bold, then the others that meet every answer, by the paper's weighted total "
        "at the study's weights" + ("; † fails analytic mechanics" if fails else "")
    )
    if tree.get("not_asked"):
        legend += ". Not asked (no answer changes the engines): " + "; ".join(
            f"{q['question']} ({q['why']})" for q in tree["not_asked"]
        )
    ax.text(0.05, height - 0.12, textwrap.fill(legend, 150), fontsize=FONT - 1, va="bottom", color="#333333")
    return fig


def tree_figure_job(tree_path: str, weighted_path: str, output: str) -> None:
    """Rule figure_tree: results/report/figures/tree.png."""
    from pathlib import Path

    tree = read_tree(tree_path)
    weighted = pd.read_csv(weighted_path)
    totals = dict(zip(weighted["engine"], weighted["total"].astype(float)))
    fig = draw_tree(tree, totals)
    Path(output).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(output, dpi=200)
