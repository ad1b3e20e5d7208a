// optri explorer: replays traces recorded by optri.trace (embedded as JSON by
// optri.teaching.explorer); nothing here recomputes the DP.
(function () {
  "use strict";
  const D = JSON.parse(document.getElementById("optri-data").textContent);
  const n = D.n;
  const KINDS = ["call", "hit", "candidate", "store"];
  const SVGNS = "http://www.w3.org/2000/svg";
  const $ = (id) => document.getElementById(id);

  let T = null; // the trace shown
  let step = 0; // events applied
  let board = null;
  let timer = null;

  // ---- values: numbers, "inf"/"-inf", or arrays of them (lexicographic pairs)
  const num = (x) => (x === "inf" ? Infinity : x === "-inf" ? -Infinity : x);
  function fmt(x) {
    if (x === null || x === undefined) return "";
    if (Array.isArray(x)) return "(" + x.map(fmt).join(", ") + ")";
    const v = num(x);
    if (v === Infinity) return "\u221e";
    if (v === -Infinity) return "\u2212\u221e";
    return Number.isInteger(v) ? String(v) : String(+v.toPrecision(6));
  }
  function less(a, b) {
    if (Array.isArray(a)) {
      for (let t = 0; t < a.length; t++) {
        const x = num(a[t]), y = num(b[t]);
        if (x !== y) return x < y;
      }
      return false;
    }
    return num(a) < num(b);
  }
  const key = (i, j) => i * n + j;
  // chord (i, j), 0-based vertices, is the paper's w[i+1, j]: sub-polygon v_{i+1}..v_{j+1}
  const chordName = (i, j) => "w[" + (i + 1) + "," + j + "]";
  const subName = (i, j) => "v" + (i + 1) + "\u2026v" + (j + 1);

  // ---- the board: what the events applied so far have written
  function fresh() {
    return { val: new Map(), split: new Map(), tried: new Map(), counts: [0, 0, 0, 0] };
  }
  function apply(b, e) {
    const kind = e[0], i = e[1], j = e[2], k = e[3], v = e[4];
    b.counts[kind]++;
    if (kind === 2) {
      let t = b.tried.get(key(i, j));
      if (!t) { t = new Map(); b.tried.set(key(i, j), t); }
      t.set(k, v);
    } else if (kind === 3) {
      b.val.set(key(i, j), v);
      b.split.set(key(i, j), k);
    }
  }
  function goTo(s) {
    s = Math.max(0, Math.min(T.events.length, s));
    if (board === null || s < step) { board = fresh(); step = 0; }
    while (step < s) apply(board, T.events[step++]);
    render();
  }
  function chordsUnder(i, j) { // stored chords of the optimal triangulation of v_i..v_j
    const out = [], stack = [[i, j]];
    while (stack.length) {
      const [a, b] = stack.pop();
      if (b - a < 2 || !board.split.has(key(a, b))) continue;
      const k = board.split.get(key(a, b));
      if (k < 0) continue;
      out.push([a, k, b]);
      stack.push([a, k], [k, b]);
    }
    return out;
  }

  // ---- the polygon
  const svg = $("poly");
  function svgEl(name, attrs, parent) {
    const el = document.createElementNS(SVGNS, name);
    for (const a in attrs) el.setAttribute(a, attrs[a]);
    if (parent) parent.appendChild(el);
    return el;
  }
  const pts = D.points;
  const ptsOf = (idx) => idx.map((v) => pts[v][0].toFixed(1) + "," + pts[v][1].toFixed(1)).join(" ");
  const gSub = svgEl("g", {}, svg), gTris = svgEl("g", {}, svg), gTop = svgEl("g", {}, svg);
  svgEl("polygon", { points: ptsOf([...Array(n).keys()]), class: "ring" }, gTop);
  const cx = pts.reduce((s, p) => s + p[0], 0) / n, cy = pts.reduce((s, p) => s + p[1], 0) / n;
  pts.forEach((p, v) => {
    svgEl("circle", { cx: p[0], cy: p[1], r: 3, class: "vertex" }, gTop);
    const dx = p[0] - cx, dy = p[1] - cy, len = Math.hypot(dx, dy) || 1;
    const label = svgEl("text", { x: p[0] + (dx / len) * 16, y: p[1] + (dy / len) * 16, class: "vlabel" }, gTop);
    label.textContent = D.labels[v];
  });
  function drawPolygon(sub, tris, cls) {
    gSub.replaceChildren();
    gTris.replaceChildren();
    if (sub) {
      const idx = [];
      for (let v = sub[0]; v <= sub[1]; v++) idx.push(v);
      svgEl("polygon", { points: ptsOf(idx), class: "sub" }, gSub);
      svgEl("line", { x1: pts[sub[0]][0], y1: pts[sub[0]][1], x2: pts[sub[1]][0], y2: pts[sub[1]][1], class: "chord" }, gSub);
    }
    for (const [t, c] of tris) svgEl("polygon", { points: ptsOf(t), class: c || cls }, gTris);
  }

  // ---- the table, in the paper's layout: chord (i, j) above at (i, j-1), below at (j, i)
  const cells = [];
  function buildTable() {
    const table = $("table");
    table.replaceChildren();
    const head = table.insertRow();
    head.appendChild(document.createElement("th"));
    for (let c = 0; c < n; c++) {
      const th = document.createElement("th");
      th.textContent = c + 1;
      head.appendChild(th);
    }
    for (let r = 0; r < n; r++) {
      const tr = table.insertRow();
      const th = document.createElement("th");
      th.textContent = r + 1;
      tr.appendChild(th);
      cells[r] = [];
      for (let c = 0; c < n; c++) {
        const td = tr.insertCell();
        cells[r][c] = td;
        let chord = null;
        if (r === c) { td.textContent = "0"; td.className = "diag"; }
        else if (c === n - 1) { td.textContent = "X"; td.className = "unused"; }
        else if (r < c) { chord = [r, c + 1]; td.className = "upper"; }
        else if (r === c + 1) { td.textContent = "(" + (r + 1) + "," + (c + 1) + ")"; td.className = "side"; }
        else { chord = [c, r]; td.className = "lower"; }
        if (chord && chord[1] - chord[0] >= 2) {
          td.dataset.i = chord[0];
          td.dataset.j = chord[1];
          td.addEventListener("mouseenter", () => hover(chord[0], chord[1]));
          td.addEventListener("mouseleave", () => render());
        }
      }
    }
  }
  const upperCell = (i, j) => cells[i][j - 1];
  const lowerCell = (i, j) => cells[j][i];
  function lowerText(i, j) {
    const tried = board.tried.get(key(i, j));
    if (!tried) return "";
    let best = board.split.has(key(i, j)) ? board.split.get(key(i, j)) : null;
    if (best === null) {
      for (const [k, v] of tried) if (best === null || less(v, tried.get(best))) best = k;
    }
    return [...tried.keys()].sort((a, b) => a - b)
      .map((k) => (k === best ? k + 1 + "*" : String(k + 1))).join(",");
  }
  let marked = [];
  function mark(el, cls) { el.classList.add(cls); marked.push([el, cls]); }
  function paintTable(ev, end) {
    for (const [el, cls] of marked) el.classList.remove(cls);
    marked = [];
    for (let i = 0; i < n; i++) {
      for (let j = i + 2; j < n; j++) {
        const up = upperCell(i, j), lo = lowerCell(i, j), kk = key(i, j);
        up.textContent = board.val.has(kk) ? fmt(board.val.get(kk)) : "";
        lo.textContent = lowerText(i, j);
        up.classList.toggle("filled", board.val.has(kk));
      }
    }
    if (end) {
      for (const [a, , b] of chordsUnder(0, n - 1)) {
        mark(upperCell(a, b), "opt");
        mark(lowerCell(a, b), "opt");
      }
      return;
    }
    if (!ev) return;
    const kind = ev[0], i = ev[1], j = ev[2], k = ev[3];
    const cls = kind === 1 ? "hit" : "cur";
    mark(upperCell(i, j), cls); // a side (j = i + 1) lights its diagonal cell w[i+1, i+1]
    mark(lowerCell(i, j), cls);
    if (kind === 2) {
      for (const [a, b] of [[i, k], [k, j]]) mark(upperCell(a, b), "inp");
    }
  }

  // ---- pseudocode and counters
  function buildCode() {
    const pre = $("code");
    pre.replaceChildren();
    T.code.forEach((text) => {
      const div = document.createElement("div");
      div.className = "line";
      div.textContent = text;
      pre.appendChild(div);
    });
  }
  function paintCode(ev, end) {
    const lines = $("code").children;
    let at = -1;
    if (end) at = T.lines.end;
    else if (ev) {
      const name = KINDS[ev[0]];
      at = ev[2] - ev[1] === 1 && T.lines[name + "Side"] !== undefined ? T.lines[name + "Side"] : T.lines[name];
    }
    for (let t = 0; t < lines.length; t++) lines[t].classList.toggle("now", t === at);
  }
  function describe(ev) { // the same sentences as optri.teaching.board.describe
    const kind = ev[0], i = ev[1], j = ev[2], k = ev[3], v = ev[4];
    const name = chordName(i, j);
    if (j - i === 1) {
      const what = ["call", "look-up", "candidate", "store"][kind];
      return what + " " + name + ": the side v" + (i + 1) + " v" + (j + 1) + ", no triangle (0)";
    }
    const sub = name + " (" + subName(i, j) + ")";
    if (kind === 0) return "call " + sub;
    if (kind === 1) return "look-up " + sub + " = " + fmt(v) + ": answered from the table, no recursion";
    if (kind === 2) {
      return "candidate " + sub + ": split at v" + (k + 1) + ", triangle v" + (i + 1) + " v" + (k + 1) +
        " v" + (j + 1) + ", gives " + fmt(v);
    }
    return "store " + sub + " = " + fmt(v) + ", optimal split " + (k === null ? "none" : "v" + (k + 1));
  }

  // ---- one picture of the current step
  function render() {
    const total = T.events.length;
    const end = step === total;
    const ev = step > 0 ? T.events[step - 1] : null;
    paintTable(ev, end);
    paintCode(ev, end);
    if (end) {
      const tris = chordsUnder(0, n - 1);
      drawPolygon(null, tris.map((t) => [t, "opt"]));
      $("status").textContent = "Optimum " + chordName(0, n - 1) + " = " + fmt(board.val.get(key(0, n - 1))) +
        ". Traced back from the stored splits: triangles " +
        tris.map((t) => "v" + (t[0] + 1) + "v" + (t[1] + 1) + "v" + (t[2] + 1)).join(", ") + ".";
    } else if (ev) {
      const kind = ev[0], i = ev[1], j = ev[2], k = ev[3];
      const tris = [];
      if (k !== null && kind >= 2) tris.push([[i, k, j], kind === 2 ? "cand" : "stored"]);
      drawPolygon([i, j], tris);
      $("status").textContent = describe(ev);
    } else {
      drawPolygon(null, []);
      $("status").textContent = "The empty table: the diagonal (the sides, w[i,i] = 0) is set; press step or play.";
    }
    KINDS.forEach((name, t) => { $("n-" + name).textContent = board.counts[t] + " / " + T.counts[name]; });
    $("stepno").textContent = step + " / " + total;
    $("scrub").max = total;
    $("scrub").value = step;
    $("optimum").textContent = end ? fmt(board.val.get(key(0, n - 1))) : "?";
    $("play").textContent = timer ? "\u2016 pause" : "\u25b6 play";
  }
  function hover(i, j) {
    const kk = key(i, j);
    if (board.val.has(kk)) {
      drawPolygon([i, j], chordsUnder(i, j).map((t) => [t, "opt"]));
      $("status").textContent = chordName(i, j) + " = " + fmt(board.val.get(kk)) +
        ": sub-polygon " + subName(i, j) + " and its optimal triangles";
    } else {
      drawPolygon([i, j], []);
      $("status").textContent = chordName(i, j) + ": sub-polygon " + subName(i, j) + ", not computed yet";
    }
  }

  // ---- controls
  function pause() { if (timer) { clearInterval(timer); timer = null; } render(); }
  function play() {
    if (timer) return;
    if (step === T.events.length) goTo(0);
    timer = setInterval(() => {
      if (step >= T.events.length) { pause(); return; }
      goTo(step + 1);
    }, 1000 / Number($("speed").value));
    render();
  }
  function setMethod(m) {
    if (!D.traces[m]) throw new Error("no trace for method " + m);
    if (timer) pause();
    T = D.traces[m];
    $("method").value = m;
    board = null;
    buildCode();
    $("algo").textContent = T.title;
    goTo(0);
  }
  const methodSel = $("method");
  Object.keys(D.traces).forEach((m) => {
    const o = document.createElement("option");
    o.value = m;
    o.textContent = D.traces[m].label;
    methodSel.appendChild(o);
  });
  methodSel.addEventListener("change", () => setMethod(methodSel.value));
  $("first").addEventListener("click", () => { pause(); goTo(0); });
  $("back").addEventListener("click", () => { pause(); goTo(step - 1); });
  $("step").addEventListener("click", () => { pause(); goTo(step + 1); });
  $("last").addEventListener("click", () => { pause(); goTo(T.events.length); });
  $("play").addEventListener("click", () => (timer ? pause() : play()));
  $("scrub").addEventListener("input", () => { pause(); goTo(Number($("scrub").value)); });
  $("speed").addEventListener("input", () => {
    $("speedval").textContent = $("speed").value + " steps/s";
    if (timer) { clearInterval(timer); timer = null; play(); }
  });
  document.addEventListener("keydown", (e) => {
    if (e.target && e.target.tagName === "SELECT") return;
    if (e.key === "ArrowRight") { pause(); goTo(step + 1); }
    else if (e.key === "ArrowLeft") { pause(); goTo(step - 1); }
    else if (e.key === " ") { e.preventDefault(); timer ? pause() : play(); }
  });

  buildTable();
  setMethod(D.start);
  $("speedval").textContent = $("speed").value + " steps/s";

  // ---- the API for tests and embedding (0-based indices, like optri.trace)
  window.optri = {
    state() {
      const ev = step > 0 ? T.events[step - 1] : null;
      return {
        step: step,
        total: T.events.length,
        method: Object.keys(D.traces).find((m) => D.traces[m] === T),
        cell: ev ? [ev[1], ev[2]] : null,
        k: ev ? ev[3] : null,
        value: ev ? num(ev[4]) : null,
        kind: ev ? KINDS[ev[0]] : null,
        counts: Object.fromEntries(KINDS.map((name, t) => [name, board.counts[t]])),
      };
    },
    step() { pause(); goTo(step + 1); return this.state(); },
    back() { pause(); goTo(step - 1); return this.state(); },
    first() { pause(); goTo(0); return this.state(); },
    last() { pause(); goTo(T.events.length); return this.state(); },
    play: play,
    pause: pause,
    method(m) { if (m !== undefined) setMethod(m); return this.state().method; },
    methods: Object.keys(D.traces),
  };
})();
