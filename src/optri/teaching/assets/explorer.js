// optri explorer. The page carries the polygon, its chord mask and its triangle weights
// w(i, k, j) (embedded by optri.teaching.explorer); this script runs the recurrence itself,
// in the same order as optri's Python engines (memo: Algorithm 3.1 top-down; table:
// bottom-up by chord length; naive: no table), and checks its counts against the ones
// optri recorded. Every piece of user text reaches the page through textContent only.
(function () {
  "use strict";
  const D = JSON.parse(document.getElementById("optri-data").textContent);
  const KINDS = ["call", "side", "hit", "candidate", "store"];
  const CALL = 0, SIDE = 1, HIT = 2, CAND = 3, STORE = 4;
  const SVGNS = "http://www.w3.org/2000/svg";
  const $ = (id) => document.getElementById(id);
  const el = (tag, cls, text) => {
    const e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    return e;
  };

  // ---- values: numbers, "inf"/"-inf", or arrays of them (lexicographic objectives)
  const num = (x) => (Array.isArray(x) ? x.map(num) : x === "inf" ? Infinity : x === "-inf" ? -Infinity : x);
  function fmt(x) {
    if (x === null || x === undefined) return "";
    if (Array.isArray(x)) return "(" + x.map(fmt).join(", ") + ")";
    if (x === Infinity) return "\u221e";
    if (x === -Infinity) return "\u2212\u221e";
    return Number.isInteger(x) ? String(x) : String(+x.toPrecision(6));
  }
  const OBJ = D.objective; // components, e.g. ["sum"], ["max"], ["sum", "max"]
  const LEX = OBJ.length > 1;
  const RTOL = 1e-12; // optri.objective.LEX_TIE_RTOL
  const comb1 = (c, a, b, w) => (c === "sum" ? a + b + w : Math.max(a, b, w));
  const combine = LEX ? (a, b, w) => OBJ.map((c, t) => comb1(c, a[t], b[t], w[t])) : (a, b, w) => comb1(OBJ[0], a, b, w);
  function tied(x, y) {
    if (Number.isInteger(x) && Number.isInteger(y)) return false;
    if (!isFinite(x) || !isFinite(y)) return false;
    return Math.abs(x - y) <= RTOL * Math.max(Math.abs(x), Math.abs(y));
  }
  function less(a, b) {
    if (!LEX) return a < b;
    for (let t = 0; t < a.length - 1; t++) {
      if (a[t] === b[t] || tied(a[t], b[t])) continue;
      return a[t] < b[t];
    }
    return a[a.length - 1] < b[b.length - 1];
  }
  const zeroOf = (c) => (c === "sum" ? 0 : -Infinity);
  const NEUTRAL = LEX ? OBJ.map(zeroOf) : zeroOf(OBJ[0]);
  const WORST = LEX ? OBJ.map(() => Infinity) : Infinity;

  // ---- the problem: n, drawing points, labels, chord mask, triangle weights
  let P = null;
  function problemFrom(n, points, labels, ok, weightOf, values) {
    const tw = new Array(n * n * n);
    const okm = new Uint8Array(n * n);
    for (let i = 0; i < n; i++) for (let j = 0; j < n; j++) okm[i * n + j] = ok(i, j) ? 1 : 0;
    for (let i = 0; i + 1 < n; i++) { okm[i * n + i + 1] = 1; okm[(i + 1) * n + i] = 1; }
    okm[n - 1] = okm[(n - 1) * n] = 1; // the side v_n v_1 closes the polygon: the root chord
    for (let i = 0; i < n; i++) {
      for (let j = i + 2; j < n; j++) {
        if (!okm[i * n + j]) continue;
        for (let k = i + 1; k < j; k++) {
          if (okm[i * n + k] && okm[k * n + j]) tw[(i * n + j) * n + k] = weightOf(i, k, j);
        }
      }
    }
    return { n, points, labels, okm, tw, values };
  }
  function embeddedProblem() {
    const n = D.n;
    const mask = D.mask; // "1"/"0" per chord (i, j), i < j, row by row; null: every chord
    const at = [];
    let t = 0;
    for (let i = 0; i < n; i++) { at.push(t - i - 1); t += n - i - 1; }
    const ok = mask === null ? () => true : (i, j) => mask[at[Math.min(i, j)] + Math.max(i, j)] === "1";
    const pre = okOnly(n, ok);
    let c = 0;
    const vals = new Map();
    for (let i = 0; i < n; i++) for (let j = i + 2; j < n; j++) {
      if (!pre(i, j)) continue;
      for (let k = i + 1; k < j; k++) if (pre(i, k) && pre(k, j)) vals.set((i * n + j) * n + k, num(D.tw[c++]));
    }
    if (c !== D.tw.length) fail("the page's triangle weights do not match its chord mask");
    return problemFrom(n, D.points, D.labels, pre, (i, k, j) => vals.get((i * n + j) * n + k), D.values);
  }
  function okOnly(n, ok) {
    return (i, j) => j - i === 1 || (i === 0 && j === n - 1) || ok(i, j);
  }
  const tri = (i, k, j) => P.tw[(i * P.n + j) * P.n + k];
  const usable = (i, j) => P.okm[i * P.n + j] === 1;
  function splits(i, j) {
    const out = [];
    for (let k = i + 1; k < j; k++) if (usable(i, k) && usable(k, j)) out.push(k);
    return out;
  }

  // ---- the three evaluation orders, event by event (kind, i, j, k, value)
  function run(method) {
    const n = P.n, ev = [];
    const push = (kind, i, j, k, v) => ev.push([kind, i, j, k, v]);
    if (method === "table") {
      const cost = new Map();
      const get = (p, q) => (q - p === 1 ? NEUTRAL : cost.get(p * n + q));
      for (let d = 2; d < n; d++) {
        for (let i = 0; i + d < n; i++) {
          const j = i + d;
          if (!usable(i, j)) continue;
          let best = WORST, arg = -1;
          for (const k of splits(i, j)) {
            const a = get(i, k); push(k - i === 1 ? SIDE : HIT, i, k, null, a);
            const b = get(k, j); push(j - k === 1 ? SIDE : HIT, k, j, null, b);
            const c = combine(a, b, tri(i, k, j));
            push(CAND, i, j, k, c);
            if (less(c, best)) { best = c; arg = k; }
          }
          cost.set(i * n + j, best);
          push(STORE, i, j, arg >= 0 ? arg : null, best);
        }
      }
      return ev;
    }
    const memo = method === "memo", cost = new Map();
    const frame = (i, j) => ({ i, j, ks: splits(i, j), t: 0, half: 0, a: null, best: WORST, arg: -1 });
    const stack = [frame(0, n - 1)];
    push(CALL, 0, n - 1, null, null);
    function deliver(f, v) {
      if (f.half === 0) { f.a = v; f.half = 1; return; }
      const k = f.ks[f.t];
      const c = combine(f.a, v, tri(f.i, k, f.j));
      push(CAND, f.i, f.j, k, c);
      if (less(c, f.best)) { f.best = c; f.arg = k; }
      f.half = 0; f.t++;
    }
    while (stack.length) {
      const f = stack[stack.length - 1];
      if (f.t === f.ks.length) {
        stack.pop();
        if (memo) cost.set(f.i * n + f.j, f.best);
        push(STORE, f.i, f.j, f.arg >= 0 ? f.arg : null, f.best);
        if (stack.length) deliver(stack[stack.length - 1], f.best);
        continue;
      }
      const k = f.ks[f.t];
      const p = f.half === 0 ? f.i : k, q = f.half === 0 ? k : f.j;
      push(CALL, p, q, null, null);
      const known = q - p === 1 ? NEUTRAL : memo ? cost.get(p * n + q) : undefined;
      if (known === undefined) { stack.push(frame(p, q)); continue; }
      if (memo) push(q - p === 1 ? SIDE : HIT, p, q, null, known);
      deliver(f, known);
    }
    return ev;
  }
  const countsOf = (ev) => {
    const c = Object.fromEntries(KINDS.map((k) => [k, 0]));
    for (const e of ev) c[KINDS[e[0]]]++;
    return c;
  };

  // ---- the cells of a trace, in the order they are stored (steps grouped by cell)
  function cellsOf(ev) {
    const open = new Map(), out = [], byKey = new Map();
    ev.forEach((e, s) => {
      const kk = e[1] * P.n + e[2];
      if (e[0] === CAND) {
        if (!open.has(kk)) open.set(kk, []);
        open.get(kk).push(s);
      } else if (e[0] === STORE) {
        const cell = { i: e[1], j: e[2], k: e[3], value: e[4], store: s, cands: open.get(kk) || [] };
        open.delete(kk);
        byKey.set(kk, out.length);
        out.push(cell);
      }
    });
    return { list: out, byKey };
  }

  // ---- state
  let T = null; // {name, events, cells, counts}
  let traces = {};
  let step = 0; // events applied
  let board = null;
  let timer = null;
  let openCell = -1; // the cell expanded in the list
  const predict = { on: false, asking: null, right: 0, asked: 0, last: "" };

  function fresh() {
    return { val: new Map(), split: new Map(), tried: new Map(), counts: [0, 0, 0, 0, 0] };
  }
  function apply(b, e) {
    const kind = e[0], kk = e[1] * P.n + e[2];
    b.counts[kind]++;
    if (kind === CAND) {
      if (!b.tried.has(kk)) b.tried.set(kk, new Map());
      b.tried.get(kk).set(e[3], e[4]);
    } else if (kind === STORE) {
      b.val.set(kk, e[4]);
      b.split.set(kk, e[3]);
    }
  }
  function goTo(s) {
    s = Math.max(0, Math.min(T.events.length, s));
    if (board === null || s < step) { board = fresh(); step = 0; }
    while (step < s) apply(board, T.events[step++]);
    render();
  }
  const key = (i, j) => i * P.n + j;
  function chordsUnder(i, j) {
    const out = [], stack = [[i, j]];
    while (stack.length) {
      const [a, b] = stack.pop();
      if (b - a < 2 || !board.split.has(key(a, b))) continue;
      const k = board.split.get(key(a, b));
      if (k === null) continue;
      out.push([a, k, b]);
      stack.push([a, k], [k, b]);
    }
    return out;
  }

  // ---- names in the paper's notation: chord (i, j), 0-based, is w[i+1, j] (the chain
  // A_{i+1} ... A_j), the sub-polygon v_{i+1} ... v_{j+1}; vertex values are p_0 ... p_{n-1}
  const cellName = (i, j) => "w[" + (i + 1) + "," + j + "]";
  const vname = (v) => "v" + (v + 1);
  const subName = (i, j) => vname(i) + "\u2026" + vname(j);
  const NAMED = ["perimeter", "diagonal", "area", "max_angle", "min_angle", "aspect_ratio"];
  function triTerm(i, k, j) { // the triangle's weight, as a formula
    if (D.weight === "product" && !LEX) return "p" + i + "\u00b7p" + k + "\u00b7p" + j;
    const name = !LEX && NAMED.includes(D.weight) ? D.weight : "w";
    return name + "(" + vname(i) + "," + vname(k) + "," + vname(j) + ")";
  }
  function arithmetic(i, j, k, c) { // w[1,4] <- w[1,1] + w[2,4] + p0·p1·p4 = 0 + 10 + 25 = 35
    const got = (p, q) => (q - p === 1 ? NEUTRAL : T.cells.list[T.cells.byKey.get(key(p, q))].value);
    const a = got(i, k), b = got(k, j), w = tri(i, k, j);
    const sum = !LEX && OBJ[0] === "sum";
    const wrap = (x, y, z) => (sum ? x + " + " + y + " + " + z : (LEX ? "combine(" : "max(") + x + ", " + y + ", " + z + ")");
    return cellName(i, j) + " = " + wrap(cellName(i, k), cellName(k, j), triTerm(i, k, j)) + " = " +
      wrap(fmt(a), fmt(b), fmt(w)) + " = " + fmt(c);
  }

  // ---- the polygon
  const svg = $("poly");
  function svgEl(name, attrs, parent) {
    const e = document.createElementNS(SVGNS, name);
    for (const a in attrs) e.setAttribute(a, attrs[a]);
    if (parent) parent.appendChild(e);
    return e;
  }
  let gSub, gTris, gTop;
  const ptsOf = (idx) => idx.map((v) => P.points[v][0].toFixed(1) + "," + P.points[v][1].toFixed(1)).join(" ");
  function buildPolygon() {
    svg.replaceChildren();
    gSub = svgEl("g", {}, svg); gTris = svgEl("g", {}, svg); gTop = svgEl("g", {}, svg);
    const n = P.n, pts = P.points;
    svgEl("polygon", { points: ptsOf([...Array(n).keys()]), class: "ring" }, gTop);
    const cx = pts.reduce((s, p) => s + p[0], 0) / n, cy = pts.reduce((s, p) => s + p[1], 0) / n;
    const small = n > 16;
    pts.forEach((p, v) => {
      const dot = svgEl("circle", { cx: p[0], cy: p[1], r: small ? 2.5 : 3.5, class: "vertex" }, gTop);
      dot.dataset.v = v;
      dot.addEventListener("click", () => clickVertex(v));
      if (small && v % 5 !== 0 && v !== n - 1) return;
      const dx = p[0] - cx, dy = p[1] - cy, len = Math.hypot(dx, dy) || 1;
      const label = svgEl("text", { x: p[0] + (dx / len) * 14, y: p[1] + (dy / len) * 14, class: "vlabel" }, gTop);
      label.textContent = P.labels[v];
    });
  }
  function drawPolygon(sub, tris) {
    gSub.replaceChildren(); gTris.replaceChildren();
    const pts = P.points;
    if (sub) {
      const idx = [];
      for (let v = sub[0]; v <= sub[1]; v++) idx.push(v);
      svgEl("polygon", { points: ptsOf(idx), class: "sub" }, gSub);
      svgEl("line", { x1: pts[sub[0]][0], y1: pts[sub[0]][1], x2: pts[sub[1]][0], y2: pts[sub[1]][1], class: "chord" }, gSub);
    }
    for (const [t, c] of tris) svgEl("polygon", { points: ptsOf(t), class: c }, gTris);
  }

  // ---- the table, in the paper's layout: chord (i, j) above at (i, j-1), below at (j, i)
  let cells = [];
  function buildTable() {
    const n = P.n, table = $("table");
    table.replaceChildren();
    cells = [];
    const head = table.insertRow();
    head.appendChild(el("th"));
    for (let c = 0; c < n; c++) head.appendChild(el("th", "", String(c + 1)));
    for (let r = 0; r < n; r++) {
      const tr = table.insertRow();
      tr.appendChild(el("th", "", String(r + 1)));
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
          td.addEventListener("click", () => jumpToCell(chord[0], chord[1]));
        }
      }
    }
    zoom(P.n > 12 ? 0.7 : 1);
  }
  const upperCell = (i, j) => cells[i][j - 1];
  const lowerCell = (i, j) => cells[j][i];
  function lowerText(i, j) {
    const tried = board.tried.get(key(i, j));
    if (!tried) return "";
    let best = board.split.has(key(i, j)) ? board.split.get(key(i, j)) : null;
    if (best === null) for (const [k, v] of tried) if (best === null || less(v, tried.get(best))) best = k;
    const ks = [...tried.keys()].sort((a, b) => a - b);
    if (ks.length > 3) return (best + 1) + "* of " + ks.length;
    return ks.map((k) => (k === best ? k + 1 + "*" : String(k + 1))).join(",");
  }
  let marked = [];
  function mark(e, cls) { e.classList.add(cls); marked.push([e, cls]); }
  function paintTable(ev, end) {
    for (const [e, cls] of marked) e.classList.remove(cls);
    marked = [];
    const n = P.n;
    for (let i = 0; i < n; i++) {
      for (let j = i + 2; j < n; j++) {
        const up = upperCell(i, j), lo = lowerCell(i, j), kk = key(i, j);
        const has = board.val.has(kk);
        const text = has ? fmt(board.val.get(kk)) : "";
        if (up.textContent !== text) up.textContent = text;
        const lt = lowerText(i, j);
        if (lo.textContent !== lt) lo.textContent = lt;
        up.classList.toggle("filled", has);
      }
    }
    if (end) {
      for (const [a, , b] of chordsUnder(0, n - 1)) { mark(upperCell(a, b), "opt"); mark(lowerCell(a, b), "opt"); }
      return;
    }
    if (!ev) return;
    const kind = ev[0], i = ev[1], j = ev[2], k = ev[3];
    const cls = kind === HIT || kind === SIDE ? "hit" : "cur";
    mark(upperCell(i, j), cls);
    mark(lowerCell(i, j), cls);
    if (kind === CAND) for (const [a, b] of [[i, k], [k, j]]) mark(upperCell(a, b), "inp");
    scrollToCell(upperCell(i, j));
  }
  function scrollToCell(td) { // keep the cell in view inside the table's own scroll box
    const box = $("tablebox");
    const bx = box.getBoundingClientRect(), cx = td.getBoundingClientRect();
    if (cx.left < bx.left + 30 || cx.right > bx.right - 10) box.scrollLeft += cx.left - bx.left - bx.width / 2;
    if (cx.top < bx.top + 20 || cx.bottom > bx.bottom - 10) box.scrollTop += cx.top - bx.top - bx.height / 2;
  }
  let zoomLevel = 1;
  function zoom(z) {
    zoomLevel = Math.max(0.4, Math.min(1.5, z));
    $("table").style.fontSize = (12 * zoomLevel).toFixed(1) + "px";
    $("zoomval").textContent = Math.round(zoomLevel * 100) + "%";
    return zoomLevel;
  }

  // ---- pseudocode and counters
  function buildCode() {
    const pre = $("code");
    pre.replaceChildren();
    T.code.forEach((text) => pre.appendChild(el("div", "line", text)));
  }
  function paintCode(ev, end) {
    const lines = $("code").children;
    let at = -1;
    if (end) at = T.lines.end;
    else if (ev) {
      const name = KINDS[ev[0]];
      at = T.lines[name + "Line"] !== undefined ? T.lines[name + "Line"] : T.lines[name];
      if (ev[2] - ev[1] === 1 && T.lines.callSide !== undefined && ev[0] === CALL) at = T.lines.callSide;
    }
    for (let t = 0; t < lines.length; t++) lines[t].classList.toggle("now", t === at);
  }
  function describe(ev) {
    const kind = ev[0], i = ev[1], j = ev[2], k = ev[3], v = ev[4];
    const name = cellName(i, j);
    if (j - i === 1) {
      return (kind === CALL ? "call " : "side ") + name + ": the side " + vname(i) + " " + vname(j) + ", no triangle (" + fmt(NEUTRAL) + ")";
    }
    const sub = name + " (" + subName(i, j) + ")";
    if (kind === CALL) return "call " + sub;
    if (kind === HIT) return "hit " + sub + " = " + fmt(v) + ": answered from the table, no recursion";
    if (kind === CAND) return "candidate " + sub + ", split at " + vname(k) + ": " + arithmetic(i, j, k, v);
    return "store " + sub + " = " + fmt(v) + ", optimal split " + (k === null ? "none" : vname(k));
  }

  // ---- the cell list: one row per stored cell, expand it to see its candidates
  function buildCells() {
    const box = $("cells");
    box.replaceChildren();
    T.cells.list.forEach((c, idx) => {
      const row = el("div", "cell");
      row.dataset.idx = idx;
      const head = el("button", "cellhead", cellName(c.i, c.j));
      head.appendChild(el("span", "detail", " = " + fmt(c.value) +
        (c.k === null ? "" : "  (split " + vname(c.k) + ", " + c.cands.length + (c.cands.length === 1 ? " candidate)" : " candidates)"))));
      head.addEventListener("click", () => { openCell = openCell === idx ? -1 : idx; paintCells(true); goTo(c.store + 1); });
      row.appendChild(head);
      box.appendChild(row);
    });
  }
  function currentCell() { // the cell being worked on: the first not yet stored, or the one just stored
    const ev = step > 0 ? T.events[step - 1] : null;
    if (ev && (ev[0] === CAND || ev[0] === STORE) && T.cells.byKey.has(key(ev[1], ev[2]))) return T.cells.byKey.get(key(ev[1], ev[2]));
    let lo = 0, hi = T.cells.list.length;
    while (lo < hi) { const mid = (lo + hi) >> 1; if (T.cells.list[mid].store < step) lo = mid + 1; else hi = mid; }
    return Math.min(lo, T.cells.list.length - 1);
  }
  let shownCell = -2, shownOpen = -2;
  function paintCells(force) {
    const box = $("cells"), cur = currentCell();
    T.cells.list.forEach((c, idx) => box.children[idx].classList.toggle("future", c.store >= step));
    if (!force && cur === shownCell && openCell === shownOpen) return;
    for (const row of box.querySelectorAll(".cell.now")) row.classList.remove("now");
    for (const sub of box.querySelectorAll(".cands")) sub.remove();
    const row = box.children[cur];
    if (row) {
      row.classList.add("now");
      const bx = box.getBoundingClientRect(), rx = row.getBoundingClientRect();
      if (rx.top < bx.top || rx.bottom > bx.bottom) box.scrollTop += rx.top - bx.top - bx.height / 3;
    }
    if (openCell >= 0 && box.children[openCell]) {
      const c = T.cells.list[openCell];
      const sub = el("div", "cands");
      for (const s of c.cands) {
        const e = T.events[s];
        const line = el("div", "cand" + (e[3] === c.k ? " best" : ""), arithmetic(e[1], e[2], e[3], e[4]));
        line.addEventListener("click", () => goTo(s + 1));
        sub.appendChild(line);
      }
      box.children[openCell].appendChild(sub);
    }
    shownCell = cur; shownOpen = openCell;
  }
  // ---- one picture of the current step
  function render() {
    const total = T.events.length;
    const end = step === total;
    const ev = step > 0 ? T.events[step - 1] : null;
    paintTable(ev, end);
    paintCode(ev, end);
    if (predict.asking) {
      const c = predict.asking;
      drawPolygon([c.i, c.j], []);
      $("status").textContent = "Predict: which vertex is the apex of the optimal triangle on " + cellName(c.i, c.j) +
        " (" + subName(c.i, c.j) + ")? Click a vertex or a button below.";
    } else if (end) {
      const tris = chordsUnder(0, P.n - 1);
      drawPolygon(null, tris.map((t) => [t, "opt"]));
      $("status").textContent = "Optimum " + cellName(0, P.n - 1) + " = " + fmt(board.val.get(key(0, P.n - 1))) +
        ". Traced back from the stored splits: triangles " +
        tris.map((t) => vname(t[0]) + vname(t[1]) + vname(t[2])).join(", ") + "." + predict.last;
    } else if (ev) {
      const kind = ev[0], i = ev[1], j = ev[2], k = ev[3];
      const tris = [];
      if (k !== null && kind >= CAND) tris.push([[i, k, j], kind === CAND ? "cand" : "stored"]);
      drawPolygon([i, j], tris);
      $("status").textContent = describe(ev) + predict.last;
    } else {
      drawPolygon(null, []);
      $("status").textContent = "The empty table: the diagonal (the sides, w[i,i] = " + fmt(NEUTRAL) + ") is set; press step or play.";
    }
    paintPredict();
    KINDS.forEach((name, t) => { $("n-" + name).textContent = board.counts[t] + " / " + T.counts[name]; });
    $("stepno").textContent = step + " / " + total;
    $("scrub").max = total;
    $("scrub").value = step;
    $("optimum").textContent = end ? fmt(board.val.get(key(0, P.n - 1))) : "?";
    $("play").textContent = timer ? "\u2016 pause" : "\u25b6 play";
    paintCells(false);
  }
  function hover(i, j) {
    const kk = key(i, j);
    if (board.val.has(kk)) {
      drawPolygon([i, j], chordsUnder(i, j).map((t) => [t, "opt"]));
      $("status").textContent = cellName(i, j) + " = " + fmt(board.val.get(kk)) + ": sub-polygon " + subName(i, j) + " and its optimal triangles";
    } else {
      drawPolygon([i, j], []);
      $("status").textContent = cellName(i, j) + ": sub-polygon " + subName(i, j) + ", not computed yet";
    }
  }
  function jumpToCell(i, j) {
    const idx = T.cells.byKey.get(key(i, j));
    if (idx === undefined) return;
    openCell = idx;
    pause();
    goTo(T.cells.list[idx].store + 1);
    paintCells(true);
  }

  // ---- moving: step, back, next store, next cell, to the end; predict mode stops before
  // the first candidate of a cell with two or more splits and asks for its split
  function needsPrediction(s) {
    if (!predict.on || s >= T.events.length) return null;
    const e = T.events[s];
    if (e[0] !== CAND) return null;
    const idx = T.cells.byKey.get(key(e[1], e[2]));
    const c = T.cells.list[idx];
    if (c.cands.length < 2 || c.cands[0] !== s || c.asked) return null;
    return c;
  }
  function advanceTo(target) { // forward, stopping where predict mode asks
    target = Math.min(T.events.length, target);
    for (let s = step; s < target; s++) {
      const c = needsPrediction(s);
      if (c) { goTo(s); predict.asking = c; pause(); render(); return false; }
    }
    goTo(target);
    return true;
  }
  function forward(target) { if (!predict.asking) advanceTo(target); }
  function nextStore() {
    for (let s = step; s < T.events.length; s++) if (T.events[s][0] === STORE) return forward(s + 1);
    forward(T.events.length);
  }
  function nextCell() { // the next candidate in another cell than the one in view
    const ev = step > 0 ? T.events[step - 1] : null;
    for (let s = step; s < T.events.length; s++) {
      const e = T.events[s];
      if (e[0] === CAND && (!ev || e[1] !== ev[1] || e[2] !== ev[2])) return forward(s + 1);
    }
    forward(T.events.length);
  }
  function answer(k) {
    const c = predict.asking;
    if (!c) return null;
    const vals = c.cands.map((s) => T.events[s]);
    const right = vals.filter((e) => !less(e[4], c.value) && !less(c.value, e[4])).map((e) => e[3]);
    const mine = vals.find((e) => e[3] === k);
    if (!mine) return null;
    const ok = right.includes(k);
    c.asked = true;
    predict.asked++; if (ok) predict.right++;
    predict.asking = null;
    predict.last = "  \u2014 " + (ok ? "right: " : "not quite: ") + "you chose " + vname(k) + " (" + fmt(mine[4]) + "), the optimum splits at " +
      right.map(vname).join(" or ") + " (" + fmt(c.value) + "). Score " + predict.right + " / " + predict.asked + ".";
    openCell = T.cells.byKey.get(key(c.i, c.j));
    goTo(c.store + 1);
    paintCells(true);
    predict.last = "";
    $("status").textContent += "";
    return ok;
  }
  function clickVertex(v) { if (predict.asking) answer(v); }
  function paintPredict() {
    const box = $("choices");
    box.replaceChildren();
    $("score").textContent = predict.on || predict.asked ? "score " + predict.right + " / " + predict.asked : "";
    if (!predict.asking) return;
    const c = predict.asking;
    for (const s of c.cands) {
      const k = T.events[s][3];
      const b = el("button", "choice", vname(k));
      b.addEventListener("click", () => answer(k));
      box.appendChild(b);
    }
  }

  function pause() { if (timer) { clearInterval(timer); timer = null; } if (T) render(); }
  function play() {
    if (timer || predict.asking) return;
    if (step === T.events.length) goTo(0);
    timer = setInterval(() => {
      if (step >= T.events.length) { pause(); return; }
      if (!advanceTo(step + 1)) pause();
    }, 1000 / Number($("speed").value));
    render();
  }
  function setMethod(m) {
    if (!traces[m]) throw new Error("no trace for method " + m);
    if (timer) pause();
    T = traces[m];
    $("method").value = m;
    board = null; openCell = -1; predict.asking = null; shownCell = -2;
    for (const c of T.cells.list) c.asked = false;
    buildCode();
    buildCells();
    $("algo").textContent = T.title;
    goTo(0);
  }
  function fail(msg) {
    const box = $("problem");
    box.textContent = msg;
    box.hidden = false;
    console.error("optri explorer: " + msg);
  }

  // ---- the traces of the problem in P
  function load(checkCounts) {
    traces = {};
    for (const m of Object.keys(D.methods)) {
      if (m === "naive" && P.n > D.naiveMax) continue;
      const events = run(m);
      const counts = countsOf(events);
      if (checkCounts && JSON.stringify(counts) !== JSON.stringify(D.methods[m].counts)) {
        fail("the page's " + m + " run differs from optri's trace: " + JSON.stringify(counts) + " against " + JSON.stringify(D.methods[m].counts));
      }
      traces[m] = { name: m, events, counts, cells: cellsOf(events), title: D.methods[m].title, code: D.methods[m].code, lines: D.methods[m].lines, label: D.methods[m].label };
    }
    const sel = $("method");
    sel.replaceChildren();
    for (const m of Object.keys(traces)) { const o = el("option", "", traces[m].label); o.value = m; sel.appendChild(o); }
    buildPolygon();
    buildTable();
    predict.right = predict.asked = 0;
    setMethod(traces[D.start] ? D.start : Object.keys(traces)[0]);
  }

  // ---- the student's own polygon: typed values (product) or clicked points (geometry)
  const SIZE = 340, PAD = 40;
  function ring(n) {
    const out = [];
    for (let v = 0; v < n; v++) {
      const a = Math.PI / 2 + 2 * Math.PI * v / n;
      out.push([SIZE / 2 + Math.cos(a) * (SIZE / 2 - PAD), SIZE / 2 - Math.sin(a) * (SIZE / 2 - PAD)]);
    }
    return out;
  }
  function setValues(values) {
    if (D.weight !== "product") throw new Error("typed values need the product weight");
    values = values.map(Number);
    if (values.length < 3 || values.length > D.maxN || values.some((x) => !isFinite(x))) {
      throw new Error("give 3 to " + D.maxN + " finite numbers");
    }
    const n = values.length;
    P = problemFrom(n, ring(n), values.map((x, v) => "p" + v + "=" + fmt(x)), () => true,
      (i, k, j) => values[i] * values[k] * values[j], values);
    load(false);
    return n;
  }
  const GEOM = {
    perimeter: (a, b, c) => Math.hypot(b[0] - a[0], b[1] - a[1]) + Math.hypot(c[0] - b[0], c[1] - b[1]) + Math.hypot(c[0] - a[0], c[1] - a[1]),
    area: (a, b, c) => Math.abs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2,
  };
  function setPoints(points) { // page coordinates, y down; the weight is measured in them
    const f = GEOM[D.weight];
    if (!f) throw new Error("clicked polygons need the perimeter or area weight");
    let pts = points.map((p) => [Number(p[0]), Number(p[1])]);
    if (pts.length < 3 || pts.length > D.maxN) throw new Error("give 3 to " + D.maxN + " points");
    let area2 = 0;
    pts.forEach((p, v) => { const q = pts[(v + 1) % pts.length]; area2 += p[0] * q[1] - q[0] * p[1]; });
    if (area2 > 0) pts = [pts[0], ...pts.slice(1).reverse()]; // y down: counter-clockwise on screen
    if (!simple(pts)) throw new Error("the polygon crosses itself");
    const n = pts.length, up = pts.map((p) => [p[0], -p[1]]);
    P = problemFrom(n, pts, pts.map((_, v) => vname(v)), (i, j) => chordInside(up, i, j), (i, k, j) => f(pts[i], pts[k], pts[j]), null);
    load(false);
    return n;
  }
  const orient = (a, b, c) => (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  function crosses(a, b, c, d) {
    const o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    return o1 * o2 < 0 && o3 * o4 < 0;
  }
  function simple(pts) {
    const n = pts.length;
    for (let a = 0; a < n; a++) for (let b = a + 2; b < n; b++) {
      if (a === 0 && b === n - 1) continue;
      if (crosses(pts[a], pts[a + 1], pts[b], pts[(b + 1) % n])) return false;
    }
    return true;
  }
  function chordInside(p, i, j) { // a diagonal: crosses no side and leaves v_i into the interior
    const n = p.length;
    for (let a = 0; a < n; a++) {
      const b = (a + 1) % n;
      if (a === i || a === j || b === i || b === j) continue;
      if (crosses(p[i], p[j], p[a], p[b])) return false;
      if (orient(p[i], p[j], p[a]) === 0 && onSeg(p[i], p[j], p[a])) return false;
    }
    const prev = p[(i - 1 + n) % n], next = p[(i + 1) % n], cur = p[i];
    const convex = orient(prev, cur, next) > 0;
    const l = orient(cur, next, p[j]) > 0, r = orient(prev, cur, p[j]) > 0;
    return convex ? l && r : l || r;
  }
  function onSeg(a, b, c) {
    return Math.min(a[0], b[0]) <= c[0] && c[0] <= Math.max(a[0], b[0]) && Math.min(a[1], b[1]) <= c[1] && c[1] <= Math.max(a[1], b[1]);
  }
  let drawing = null;
  function startDrawing() {
    pause();
    drawing = [];
    svg.replaceChildren();
    gSub = svgEl("g", {}, svg); gTris = svgEl("g", {}, svg); gTop = svgEl("g", {}, svg);
    $("status").textContent = "Click the polygon's vertices in order, then press \u201csolve\u201d.";
  }
  svg.addEventListener("click", (e) => {
    if (!drawing) return;
    const r = svg.getBoundingClientRect();
    const p = [(e.clientX - r.left) * SIZE / r.width, (e.clientY - r.top) * SIZE / r.height];
    drawing.push(p);
    svgEl("circle", { cx: p[0], cy: p[1], r: 3.5, class: "vertex" }, gTop);
    if (drawing.length > 1) svgEl("polyline", { points: drawing.map((q) => q[0].toFixed(1) + "," + q[1].toFixed(1)).join(" "), class: "ring" }, gTop);
  });
  function solveInput() {
    try {
      if (drawing) { const pts = drawing; drawing = null; setPoints(pts); }
      else setValues($("values").value.split(/[\s,;]+/).filter((s) => s.length));
      $("problem").hidden = true;
    } catch (err) {
      fail(String(err.message || err));
    }
  }

  // ---- controls
  $("method").addEventListener("change", () => setMethod($("method").value));
  $("first").addEventListener("click", () => { pause(); predict.asking = null; goTo(0); });
  $("back").addEventListener("click", () => { pause(); predict.asking = null; goTo(step - 1); });
  $("step").addEventListener("click", () => { pause(); forward(step + 1); });
  $("nextstore").addEventListener("click", () => { pause(); nextStore(); });
  $("nextcell").addEventListener("click", () => { pause(); nextCell(); });
  $("last").addEventListener("click", () => { pause(); forward(T.events.length); });
  $("play").addEventListener("click", () => (timer ? pause() : play()));
  $("scrub").addEventListener("input", () => { pause(); predict.asking = null; goTo(Number($("scrub").value)); });
  $("speed").addEventListener("input", () => {
    $("speedval").textContent = $("speed").value + " steps/s";
    if (timer) { clearInterval(timer); timer = null; play(); }
  });
  $("zoomin").addEventListener("click", () => { zoom(zoomLevel * 1.25); render(); });
  $("zoomout").addEventListener("click", () => { zoom(zoomLevel / 1.25); render(); });
  $("predict").addEventListener("change", () => { predict.on = $("predict").checked; predict.asking = null; render(); });
  const canType = D.weight === "product" && !LEX, canDraw = GEOM[D.weight] !== undefined && !LEX;
  $("values").hidden = !canType;
  $("draw").hidden = !canDraw;
  $("solve").hidden = !canType && !canDraw;
  $("inputnote").textContent = canType ? "your values:" : canDraw ? "your polygon:" : "";
  if (canType && D.values) $("values").value = D.values.map(fmt).join(", ");
  $("draw").addEventListener("click", startDrawing);
  $("solve").addEventListener("click", solveInput);
  document.addEventListener("keydown", (e) => {
    const tag = e.target && e.target.tagName;
    if (tag === "SELECT" || tag === "INPUT") return;
    if (e.key === "ArrowRight") { pause(); forward(step + 1); }
    else if (e.key === "ArrowLeft") { pause(); goTo(step - 1); }
    else if (e.key === " ") { e.preventDefault(); timer ? pause() : play(); }
  });

  P = embeddedProblem();
  load(true);
  $("speedval").textContent = $("speed").value + " steps/s";

  // ---- the API for tests and embedding (0-based indices, like optri.trace)
  window.optri = {
    state() {
      const ev = step > 0 ? T.events[step - 1] : null;
      return {
        n: P.n,
        step: step,
        total: T.events.length,
        method: T.name,
        cell: ev ? [ev[1], ev[2]] : null,
        k: ev ? ev[3] : null,
        value: ev ? ev[4] : null,
        kind: ev ? KINDS[ev[0]] : null,
        counts: Object.fromEntries(KINDS.map((name, t) => [name, board.counts[t]])),
        status: $("status").textContent,
        asking: predict.asking ? [predict.asking.i, predict.asking.j] : null,
        score: [predict.right, predict.asked],
      };
    },
    step() { pause(); forward(step + 1); return this.state(); },
    back() { pause(); goTo(step - 1); return this.state(); },
    first() { pause(); goTo(0); return this.state(); },
    last() { pause(); forward(T.events.length); return this.state(); },
    nextStore() { pause(); nextStore(); return this.state(); },
    nextCell() { pause(); nextCell(); return this.state(); },
    goTo(s) { pause(); goTo(s); return this.state(); },
    play: play,
    pause: pause,
    method(m) { if (m !== undefined) setMethod(m); return T.name; },
    get methods() { return Object.keys(traces); },
    events(m) { return traces[m || T.name].events.map((e) => [KINDS[e[0]], e[1], e[2], e[3], e[4]]); },
    cells() { return T.cells.list.map((c) => ({ i: c.i, j: c.j, k: c.k, value: c.value, store: c.store, candidates: c.cands.length })); },
    arithmetic(i, j, k) {
      const e = T.events.find((x) => x[0] === CAND && x[1] === i && x[2] === j && x[3] === k);
      return e ? arithmetic(i, j, k, e[4]) : null;
    },
    predict(on) { $("predict").checked = !!on; predict.on = !!on; predict.asking = null; render(); return predict.on; },
    answer: answer,
    setValues: setValues,
    setPoints: setPoints,
    zoom: zoom,
    points() { return P.points; },
  };
})();
