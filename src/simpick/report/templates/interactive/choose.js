// The decision tree and the paper's weighted total, in the browser: the data (the tree the rule
// decision_tree wrote, the scores of results/scores/weighted.csv, the study's weights) sit in the
// JSON block beside this script; nothing is fetched.
(function () {
  "use strict";
  var root = document.getElementById("simpick-choose");
  var data = JSON.parse(document.getElementById("sc-data").textContent);
  var tree = data.tree;
  var weights = Object.assign({}, data.weights);
  var path = [];  // [{node: id, answer: index}] from the root

  function el(tag, attrs, children) {
    var node = document.createElement(tag);
    Object.keys(attrs || {}).forEach(function (k) {
      if (k === "text") { node.textContent = attrs[k]; } else { node.setAttribute(k, attrs[k]); }
    });
    (children || []).forEach(function (c) {
      node.appendChild(typeof c === "string" ? document.createTextNode(c) : c);
    });
    return node;
  }

  // The paper's weighted total: sum over the criteria of weight x score, a missing score counting
  // as 0; rank 1 = highest, equal totals share the better rank (simpick.score.scoring.weighted_table).
  function totals() {
    var out = {};
    data.engines.forEach(function (e) {
      var total = 0, excluded = [];
      data.metrics.forEach(function (m) {
        var s = data.scores[e][m.key];
        if (s === null || s === undefined) { excluded.push(m.key); } else { total += weights[m.key] * s; }
      });
      out[e] = {total: total, excluded: excluded};
    });
    data.engines.forEach(function (e) {
      out[e].rank = 1 + data.engines.filter(function (o) { return out[o].total > out[e].total; }).length;
    });
    return out;
  }

  function byTotal(engines, t) {
    var order = {};
    tree.engines.forEach(function (e, i) { order[e] = i; });
    return engines.slice().sort(function (a, b) {
      var ta = t[a] ? t[a].total : -Infinity, tb = t[b] ? t[b].total : -Infinity;
      return ta !== tb ? tb - ta : order[a] - order[b];
    });
  }

  function fact(question, engine) {
    var q = tree.questions.filter(function (x) { return x.key === question; })[0];
    return q ? q.facts[engine] : null;
  }

  // The table is built once (so an input keeps its focus while typed in); refreshWeights writes
  // the figures that follow from the weights.
  function buildWeights() {
    var table = document.getElementById("sc-weights");
    var head = el("tr", {}, [el("th", {text: "Criterion"}), el("th", {"class": "num", text: "Weight"})]);
    data.engines.forEach(function (e) { head.appendChild(el("th", {"class": "num", text: e})); });
    table.appendChild(el("thead", {}, [head]));
    var body = el("tbody");
    data.metrics.forEach(function (m) {
      var input = el("input", {type: "number", min: "0", step: "any", value: String(weights[m.key]),
                               "data-metric": m.key, "aria-label": "weight of " + m.label});
      input.addEventListener("input", function () {
        var v = parseFloat(input.value);
        weights[m.key] = isFinite(v) ? v : 0;
        update(false);
      });
      var row = el("tr", {}, [el("td", {text: m.label}), el("td", {"class": "num"}, [input])]);
      data.engines.forEach(function (e) {
        var s = data.scores[e][m.key];
        row.appendChild(el("td", {"class": "num", text: s === null ? "n/a" : s.toFixed(3)}));
      });
      body.appendChild(row);
    });
    var total = el("tr", {"class": "sc-total"}, [el("td", {text: "Total (the paper's method)"}),
                                                 el("td", {"class": "num", id: "sc-weight-sum"})]);
    var rank = el("tr", {}, [el("td", {text: "Rank"}), el("td")]);
    data.engines.forEach(function (e) {
      total.appendChild(el("td", {"class": "num sc-engine-total", "data-engine": e}));
      rank.appendChild(el("td", {"class": "num sc-engine-rank", "data-engine": e}));
    });
    body.appendChild(total);
    body.appendChild(rank);
    table.appendChild(body);
  }

  function refreshWeights(t) {
    var table = document.getElementById("sc-weights");
    Array.prototype.forEach.call(table.querySelectorAll("input[data-metric]"), function (input) {
      var key = input.getAttribute("data-metric");
      if (parseFloat(input.value) !== weights[key] && document.activeElement !== input) {
        input.value = String(weights[key]);
      }
      input.className = weights[key] !== data.weights[key] ? "sc-changed" : "";
    });
    var sum = data.metrics.reduce(function (a, m) { return a + weights[m.key]; }, 0);
    document.getElementById("sc-weight-sum").textContent = String(+sum.toFixed(6));
    Array.prototype.forEach.call(table.querySelectorAll(".sc-engine-total"), function (cell) {
      var e = cell.getAttribute("data-engine");
      cell.setAttribute("data-total", String(t[e].total));
      cell.textContent = t[e].total.toFixed(3);
    });
    Array.prototype.forEach.call(table.querySelectorAll(".sc-engine-rank"), function (cell) {
      var e = cell.getAttribute("data-engine");
      cell.textContent = String(t[e].rank);
      if (data.flags[e]) {
        cell.appendChild(el("span", {"class": "sc-flag", title: data.flags[e], text: " \u2020"}));
      }
    });
  }

  function renderRanking(t) {
    var ranking = document.getElementById("sc-ranking");
    ranking.textContent = "";
    var flagged = data.engines.filter(function (e) { return data.flags[e]; });
    if (flagged.length) {
      ranking.appendChild(el("span", {"class": "sc-flag", text: "\u2020 fails analytic mechanics: " +
        flagged.map(function (e) { return e + " " + data.flags[e]; }).join("; ") + "."}));
      ranking.appendChild(el("br"));
    }
    ranking.appendChild(document.createTextNode("Ranking by the paper's method: "));
    byTotal(data.engines, t).forEach(function (e, i) {
      if (i) { ranking.appendChild(document.createTextNode(", ")); }
      ranking.appendChild(el("span", {"class": "sc-ranked", "data-engine": e,
                                      text: t[e].rank + ". " + e + (data.flags[e] ? "\u2020" : "") + " " +
                                            t[e].total.toFixed(3)}));
    });
  }

  function renderPath() {
    var list = document.getElementById("sc-path");
    list.textContent = "";
    path.forEach(function (step, i) {
      var node = tree.nodes[step.node];
      var answer = node.answers[step.answer];
      var back = el("button", {type: "button", "class": "sc-back", text: "change"});
      back.addEventListener("click", function () { path = path.slice(0, i); update(true); });
      list.appendChild(el("li", {}, [node.text + " ", el("strong", {text: answer.label}), back]));
    });
  }

  function current() {
    var id = tree.root;
    path.forEach(function (step) { id = tree.nodes[step.node].answers[step.answer].next; });
    return tree.nodes[id];
  }

  function evidenceTable(engines) {
    var table = el("table", {"class": "sc-evidence"});
    var head = el("tr", {}, [el("th", {text: "Question"})]);
    engines.forEach(function (e) { head.appendChild(el("th", {text: e})); });
    table.appendChild(head);
    tree.questions.forEach(function (q) {
      var row = el("tr", {}, [el("td", {text: q.text + (q.asked ? "" : " (not asked)")})]);
      engines.forEach(function (e) {
        var f = q.facts[e];
        row.appendChild(el("td", {}, [f.text, el("span", {"class": "sc-source", text: f.source})]));
      });
      table.appendChild(row);
    });
    return table;
  }

  function renderCurrent(t) {
    var box = document.getElementById("sc-current");
    box.textContent = "";
    var node = current();
    root.setAttribute("data-node", node.id);
    if (node.kind === "question") {
      box.appendChild(el("p", {"class": "sc-question", "data-question": node.question, text: node.text}));
      var answers = el("div", {"class": "sc-answers"});
      node.answers.forEach(function (a, i) {
        var keeps = a.keeps.length ? "keeps " + byTotal(a.keeps, t).join(", ") : "keeps no " + data.noun;
        var button = el("button", {type: "button", "data-question": node.question, "data-answer": a.label},
                        [a.label + " ", el("span", {"class": "sc-keeps", text: "(" + keeps + ")"})]);
        button.addEventListener("click", function () { path.push({node: node.id, answer: i}); update(true); });
        answers.appendChild(button);
      });
      box.appendChild(answers);
      root.setAttribute("data-pick", "");
      return;
    }
    var dropped = [];
    path.forEach(function (step) {
      var n = tree.nodes[step.node], a = n.answers[step.answer];
      a.drops.forEach(function (d) { dropped.push({engine: d.engine, why: d.why, answer: n.text + " " + a.label}); });
    });
    if (!node.engines.length) {
      root.setAttribute("data-pick", "");
      box.appendChild(el("p", {"class": "sc-none", id: "sc-pick", "data-engine": "",
                               text: "No " + data.noun + " of this study meets all these answers."}));
    } else {
      var ordered = byTotal(node.engines, t);
      root.setAttribute("data-pick", ordered[0]);
      var pick = el("p", {"class": "sc-pick", id: "sc-pick", "data-engine": ordered[0]},
                    ["Pick: ", el("strong", {text: ordered[0]})]);
      if (ordered.length > 1) {
        pick.appendChild(document.createTextNode(
          " (meets every answer, as do " + ordered.slice(1).join(", ") + "; ordered by the paper's weighted total " +
          ordered.map(function (e) { return e + " " + t[e].total.toFixed(3); }).join(", ") + ")"));
      } else {
        pick.appendChild(document.createTextNode(" (the only " + data.noun + " that meets every answer)"));
      }
      if (data.flags[ordered[0]]) {
        pick.appendChild(el("span", {"class": "sc-flag", text: " " + data.flags[ordered[0]]}));
      }
      box.appendChild(pick);
      var leaf = el("ol", {"class": "sc-leaf", id: "sc-leaf"});
      ordered.forEach(function (e) { leaf.appendChild(el("li", {"data-engine": e, text: e})); });
      box.appendChild(leaf);
      // the simulators' tree: the profile each leaf's answers ask for, with its settings file
      // (simpick.score.profiles.name_profiles); the calibrated one where they ask for closeness to the robot
      if (node.profiles && node.profiles.length) {
        var named = {};
        node.profiles.forEach(function (p) { named[p.simulator] = p; });
        var profiles = el("ul", {"class": "sc-profiles", id: "sc-profiles"});
        ordered.forEach(function (e) {
          var p = named[e];
          if (p) {
            profiles.appendChild(el("li", {"data-engine": e, "data-variant": p.variant,
              text: p.text + (p.closest ? "; closest to the robot: " + p.closest : "")}));
          }
        });
        box.appendChild(el("p", {text: "With its settings:"}));
        box.appendChild(profiles);
      }
      box.appendChild(el("p", {text: "Why, on the study's evidence:"}));
      box.appendChild(evidenceTable(ordered));
    }
    if (dropped.length) {
      var list = el("ul", {"class": "sc-dropped"});
      dropped.forEach(function (d) {
        list.appendChild(el("li", {text: d.engine + " left out by \u201c" + d.answer + "\u201d: " + d.why}));
      });
      box.appendChild(el("p", {text: "Left out on the way:"}));
      box.appendChild(list);
    }
  }

  // The whole tree at once, each leaf's engines by the weighted total at the current weights.
  function renderOutline(t) {
    var box = document.getElementById("sc-outline");
    box.textContent = "";
    function branch(id) {
      var node = tree.nodes[id];
      if (node.kind === "leaf") {
        if (!node.engines.length) {
          return el("span", {"class": "sc-none sc-outline-leaf", "data-leaf": id, "data-engines": "", text: "none"});
        }
        var ordered = byTotal(node.engines, t);
        var named = ordered.map(function (e) { return e + (data.flags[e] ? "\u2020" : ""); });
        return el("span", {"class": "sc-outline-leaf", "data-leaf": id, "data-engines": ordered.join(" ")},
                  [el("strong", {text: named[0]}),
                   named.length > 1 ? " (then " + named.slice(1).join(", ") + ")" : ""]);
      }
      var list = el("ul");
      var seen = {};
      node.answers.forEach(function (a) {
        if (seen[a.next]) { seen[a.next].firstChild.textContent += " / " + a.label; return; }
        var item = el("li", {}, [el("em", {text: a.label}), " \u2192 ", branch(a.next)]);
        seen[a.next] = item;
        list.appendChild(item);
      });
      return el("span", {}, [node.text, list]);
    }
    box.appendChild(branch(tree.root));
  }

  function update(treeOnly) {
    var t = totals();
    if (!treeOnly) { refreshWeights(t); renderRanking(t); renderOutline(t); }
    renderPath();
    renderCurrent(t);
  }

  document.getElementById("sc-reset").addEventListener("click", function () {
    weights = Object.assign({}, data.weights);
    update(false);
  });
  var notAsked = document.getElementById("sc-not-asked");
  if (tree.not_asked.length) {
    notAsked.textContent = "Not asked, since no answer would change the engines: " + tree.not_asked.map(
      function (q) { return q.question + " (" + q.why + ")"; }).join("; ") + ".";
  }
  buildWeights();
  update(false);
  root.setAttribute("data-ready", "true");
})();
