"""The mutations ``run.py`` applies to a copy of the repository, one at a time.

Each names a file, an exact piece of its text (found exactly once), the text
that replaces it, and the pytest arguments (test files, ``-k`` filters) whose
run must then fail. Prefer lines whose meaning is stable, so the list still
applies after refactoring; a mutation whose old text is gone is reported
"stale", to be updated, not counted.
"""

from __future__ import annotations

from typing import NamedTuple


class Mutation(NamedTuple):
    """One deliberate bug and the tests that must catch it."""

    name: str
    file: str  # from the repository root
    old: str
    new: str
    tests: tuple[str, ...]  # pytest arguments, run with -x -q
    why: str = ""


M = Mutation
ENGINES = "tests/test_core_engines.py"
TIES = "tests/test_core_ties.py"
FAST = "tests/test_fast_engine.py"
RESULT = "tests/test_core_result.py"
ERRORS = "tests/test_core_errors.py"
POLYLINE = "tests/test_mesh_polyline.py"
MESH = "tests/test_mesh_fill.py"
RESUME = "tests/test_batch_resume.py"
MASK = "tests/test_simple_mask.py"
SIMPLE = "tests/test_simple_solve.py"
WEIGHTS = "tests/test_core_weights.py"
TWINS = "tests/test_weights.py"
MINPLUS = "tests/test_minplus_kernels.py"
GPU_SIM = ("tests/test_gpu_sim.py", "-k", "small")  # the simulator cases, tiny tiles
GPU_PTX = "tests/test_gpu_ptx.py"
TRACE = "tests/test_teaching_trace.py"
PREDICATES = "tests/test_exact_predicates.py"
DOM_BRUTE = "tests/test_domains_brute.py"
DOM_INV = "tests/test_domains_invariants.py"
BATCH_HOLES = "tests/test_batch_formats.py"

MUTATIONS: list[Mutation] = [
    # --- the list: two-phase rule, ties, check(), CLI errors, 3-D limit ---------
    M(
        "two-phase-off",
        "src/optri/objective.py",
        'return self.is_lex and self.components[0] == "max"',
        "return False",
        (ENGINES, "-k", "two_phases"),
        "max-led pairs solved in one (inexact) lexicographic pass",
    ),
    M(
        "two-phase-skipped-for-fast",
        "src/optri/solve.py",
        'if objective.two_phase and method != "brute":',
        'if objective.two_phase and method not in ("brute", "fast"):',
        (FAST, "-k", "max_led"),
        "the compiled engine gets the max-led pair in one pass",
    ),
    M(
        "minplus-ignores-gate",
        "src/optri/engines/jit.py",
        'if problem.gates or problem.objective.components != ("sum",):',
        'if problem.objective.components != ("sum",):',
        (FAST, "-k", "max_led"),
        "a gated sum of perimeters/diagonals runs on the gateless min-plus kernel",
    ),
    M(
        "compiled-gate-excludes-equal",
        "src/optri/engines/_jit_kernels.py",
        "> gate[0]:",
        ">= gate[0]:",
        (FAST, "-k", "max_led"),
        "the bottleneck itself gated out (the threshold is loosened by tie_ceiling: only a "
        "zero bottleneck, which it leaves as is, shows it)",
    ),
    M(
        "float32-gate-not-widened",
        "src/optri/engines/jit.py",
        "return float(np.nextafter(np.float32(thr), np.float32(np.inf)))",
        "return float(np.float32(thr))",
        (FAST, "-k", "float32_gate"),
        "a float32 bottleneck rounded down gates out its own triangle",
    ),
    M(
        "python-gate-excludes-equal",
        "src/optri/engines/problem.py",
        "if g(i, k, j) > thr:",
        "if g(i, k, j) >= thr:",
        (ENGINES, "-k", "two_phases or lexicographic"),
        "the Python engines gate out the bottleneck triangle",
    ),
    M(
        "cell-ties-to-last",
        "src/optri/engines/recurrence.py",
        "if less(c, best):",
        "if not less(best, c):",
        (TIES,),
        "memo/table keep the last of equal splits",
    ),
    M(
        "splits-in-decreasing-order",
        "src/optri/engines/recurrence.py",
        "return range(i + 1, j)",
        "return range(j - 1, i, -1)",
        (TIES,),
        "splits tried largest first: ties go to the largest k",
    ),
    M(
        "objective-less-is-le",
        "src/optri/objective.py",
        "return lex_less if self.is_lex else operator.lt",
        "return lex_less if self.is_lex else operator.le",
        (TIES,),
        "a tie replaces the best split",
    ),
    M(
        "brute-ties-to-last",
        "src/optri/engines/brute.py",
        "if best_tris is None or objective.less(c, best_cost):",
        "if best_tris is None or not objective.less(best_cost, c):",
        (TIES,),
        "brute force keeps the last optimal triangulation",
    ),
    M(
        "compiled-ties-to-last",
        "src/optri/engines/_jit_kernels.py",
        "if v1 < b1:",
        "if v1 <= b1:",
        (TIES,),
        "the generic kernel keeps the last of equal splits",
    ),
    M(
        "minplus-ties-to-last",
        "src/optri/engines/_minplus.py",
        "for kk in range(ri.shape[0]):\n        if ri[kk] + rj[kk] == best:",
        "for kk in range(ri.shape[0] - 1, -1, -1):\n        if ri[kk] + rj[kk] == best:",
        (TIES,),
        "the min-plus traceback keeps the last of equal splits",
    ),
    M(
        "compiled-lex-ties-to-last",
        "src/optri/objective.py",  # lex_better, compiled into the kernel's best_split
        "return a2 < b2",
        "return a2 <= b2",
        (TIES,),
        "a lexicographic tie in both components replaces the best split",
    ),
    M(
        "check-ignores-crossings",
        "src/optri/result.py",
        '_require(chords_cross_free(diags), "two diagonals cross")',
        '_require(True, "two diagonals cross")',
        (RESULT,),
    ),
    M(
        "cross-free-test-inverted",
        "src/optri/result.py",
        "if stack and b > stack[-1]:",
        "if stack and b < stack[-1]:",
        (RESULT,),
    ),
    M(
        "check-allows-duplicates",
        "src/optri/result.py",
        "_require(count == (1 if side else 2),",
        "_require(count >= 1,",
        (RESULT,),
    ),
    M(
        "check-allows-clockwise",
        "src/optri/result.py",
        '_require(bool((orient(p[t0], p[t1], p[t2]) >= 0).all()), "a triangle is clockwise")',
        '_require(True, "a triangle is clockwise")',
        (RESULT,),
    ),
    M(
        "check-ignores-cost",
        "src/optri/result.py",
        "            self._check_areas(rtol)\n        if self._recompute is not None:\n"
        "            again = self._recompute(self.triangles)\n"
        "            _require(_close(again, self.weight, rtol),",
        "            self._check_areas(rtol)\n        if self._recompute is not None:\n"
        "            again = self._recompute(self.triangles)\n"
        "            _require(True,",
        (RESULT,),
    ),
    M(
        "cli-error-keeps-newlines",
        "src/optri/cli/app.py",
        """click.echo(f"optri: error: {' '.join(message.split())}", err=True)""",
        'click.echo(f"optri: error: {message}", err=True)',
        (ERRORS, "-k", "cli"),
    ),
    M(
        "cli-error-exit-1",
        "src/optri/cli/app.py",
        "sys.exit(2)",
        "sys.exit(1)",
        (ERRORS, "-k", "cli"),
    ),
    M(
        "cli-oserror-traceback",
        "src/optri/cli/app.py",
        "except OSError as exc:",
        "except NotImplementedError as exc:",
        (ERRORS, "-k", "cli"),
        "an OSError (unwritable output) escapes as a traceback",
    ),
    M(
        "cli-interrupt-exit-1",
        "src/optri/cli/app.py",
        '    click.echo("optri: interrupted", err=True)\n    return 130',
        '    click.echo("optri: interrupted", err=True)\n    return 1',
        (RESUME,),
    ),
    M(
        "stop-signal-as-ctrl-c",
        "src/optri/engines/interrupts.py",
        "raise Terminated(signum)",
        "raise KeyboardInterrupt",
        (RESUME,),
        "a batch killed by SIGTERM says 'interrupted' and exits 130, not 143",
    ),
    M(
        "interruptible-loses-the-signal",
        "src/optri/engines/interrupts.py",
        "raise cause.with_traceback(None) from None",
        "raise KeyboardInterrupt from None",
        (ERRORS, "-k", "signal"),
    ),
    M(
        "stop-handlers-not-restored",
        "src/optri/engines/interrupts.py",
        "            signal.signal(sig, handler)",
        "            pass",
        (ERRORS, "-k", "signal"),
    ),
    M(
        "valid-diagonals-skips-simplicity",
        "src/optri/simple/mask.py",
        "    require_simple(poly)\n    return _diagonals(poly)",
        "    return _diagonals(poly)",
        (MASK, "-k", "not_simple or waves"),
        "a self-crossing boundary gets a mask (or an internal error) instead of its edges named",
    ),
    M(
        "mask-walk-stop-always-internal",
        "src/optri/simple/mask.py",
        "if find_self_intersection(points) is None:",
        "if True:",
        (MASK, "-k", "waves"),
    ),
    M(
        "holes-exact-limit-exclusive",
        "src/optri/holes/modes.py",
        "n <= config.HOLES_EXACT_MAX_N",
        "n < config.HOLES_EXACT_MAX_N",
        (POLYLINE, "-k", "limit"),
    ),
    # --- engines and the recurrence ---------------------------------------------------
    M(
        "chords-skip-triangles",
        "src/optri/engines/recurrence.py",
        "for d in range(2, n):",
        "for d in range(3, n):",
        (ENGINES,),
    ),
    M(
        "walk-drops-right-half",
        "src/optri/engines/recurrence.py",
        "stack.extend(reversed(children))",
        "stack.extend(children[:1])",
        (ENGINES,),
    ),
    M(
        "export-split-shifted",
        "src/optri/engines/recurrence.py",
        "out[j, i] = split[i][j]",
        "out[j, i] = split[i][j] + 1",
        (ENGINES,),
    ),
    M(
        "export-keeps-minus-inf",
        "src/optri/engines/recurrence.py",
        "out[i, j] = 0.0 if v == -math.inf else v",
        "out[i, j] = v",
        (ENGINES,),
        'sides of a "max" table exported as -inf instead of 0',
    ),
    M(
        "memo-lookups-off-by-one",
        "src/optri/engines/memo.py",
        '"lookups": requests - misses,',
        '"lookups": requests - misses - 1,',
        (ENGINES,),
    ),
    M(
        "table-reads-lower-half",
        "src/optri/engines/table.py",
        "p, q = frame.send(cost[p][q])",
        "p, q = frame.send(cost[q][p] if p + 1 < q else cost[p][q])",
        (ENGINES,),
    ),
    M(
        "fast-auto-threshold-exclusive",
        "src/optri/engines/jit.py",
        "return problem.n >= config.FAST_AUTO_MIN_N",
        "return problem.n > config.FAST_AUTO_MIN_N",
        (FAST, "-k", "auto_default"),
    ),
    M(
        "minplus-edge-counted-once",
        "src/optri/engines/_minplus.py",
        "v = best + 2.0 * _edge(ew, i, j)",
        "v = best + _edge(ew, i, j)",
        (FAST, "-k", "brute or square"),
    ),
    M(
        "leaf4-drops-a-split",
        "src/optri/engines/_minplus.py",
        "m = _min3(t3, x30 + b03, x31 + b13)",
        "m = fmin(t3, x30 + b03)",
        (MINPLUS, "-k", "python_table"),
        "a 4 x 4 leaf forgets split (a + 3, c + 1) of cell (a + 3, c + 3)",
    ),
    M(
        "leaf4-side-gets-a-chord-cost",
        "src/optri/engines/_minplus.py",
        "x30 = _final(T, ew, mask, use_mask, i, c, t0)",
        "x30 = _final_chord(T, ew, mask, use_mask, i, c, t0)",
        (MINPLUS, "-k", "python_table or tiling"),
        "a leaf's corner cell (a + 3, a + 4), a polygon side, gets a chord's cost",
    ),
    M(
        "leaf4-reads-a-row-shifted",
        "src/optri/engines/_minplus.py",
        "return load_at(T, i, c), load_at(T, i, c + 1), load_at(T, i, c + 2), load_at(T, i, c + 3)",
        "return load_at(T, i, c), load_at(T, i, c + 1), load_at(T, i, c + 2), load_at(T, i, c + 2)",
        (MINPLUS, "-k", "python_table or tiling"),
        "a leaf starts cell (i, c + 3) from the partial minimum of (i, c + 2)",
    ),
    M(
        "square-skips-a-product",
        "src/optri/engines/_minplus.py",
        "    _product(T, mask, use_mask, _ROWS, a, m, m2, e, c, m2)\n",
        "",
        (MINPLUS, "-k", "python_table"),
        "the top-right quarter of a block never sees the splits through its bottom-left",
    ),
    M(
        "square8-one-leaf",
        "src/optri/engines/_minplus.py",
        "        _square8(T, ew, mask, use_mask, a, c)\n        return",
        "        _leaf4(T, ew, mask, use_mask, a, c)\n        return",
        (MINPLUS, "-k", "both_halves or python_table"),
        "an 8 x 8 block of the halving (n = 1000's last tile has them) solves one leaf of four",
    ),
    M(
        "square16-product-too-short",
        "src/optri/engines/_minplus.py",
        "_block(T, mask, use_mask, r, c + 8, a + 8, 8, 8)",
        "_block(T, mask, use_mask, r, c + 8, a + 8, 7, 8)",
        (MINPLUS, "-k", "python_table"),
        "16 x 16 blocks lose one split row (only blocks of a 128-tile are 16 x 16)",
    ),
    M(
        "final-returns-unrounded",
        "src/optri/engines/_minplus.py",
        "    v = T.dtype.type(v)\n    store_at(T, i, j, v)\n    return v",
        "    store_at(T, i, j, T.dtype.type(v))\n    return v",
        (MINPLUS, "-k", "tiling"),
        "a leaf carries a float32 cell's unrounded value to its neighbours",
    ),
    M(
        "far-packs-one-split-row",
        "src/optri/engines/_minplus.py",
        "transpose_8x8(T, j, kb + t, P, p + t, 0)",
        "transpose_8x8(T, j, kb, P, p + t, 0)",
        (MINPLUS, "-k", "tiling or python_table or far_product"),
        "the packed far product copies the first 8 splits' rows for every 8 (first 8 columns)",
    ),
    M(
        "far-forgets-columns-past-strips",
        "src/optri/engines/_minplus.py",
        "_product(T, mask, False, rows, ia, ib, jf, jb, k0, k1)",
        "_product(T, mask, False, rows, ia, ib, jf, jb, k0, k0)",
        (MINPLUS, "-k", "tiling or python_table or far_product"),
        "columns past the last whole 16-column strip miss their far splits",
    ),
    M(
        "far-forgets-rows-past-blocks",
        "src/optri/engines/_minplus.py",
        "_product(T, mask, False, rows, i_f, ib, ja, jf, k0, k1)",
        "_product(T, mask, False, rows, i_f, ib, ja, jf, k0, k0)",
        (MINPLUS, "-k", "tiling or python_table or far_product"),
        "rows past the last whole 4- or 8-row block miss their far splits",
    ),
    M(
        "far-8x16-block-runs-as-4x16",
        "src/optri/engines/_minplus.py",
        "outer_8x16(T, i, ja + 16 * s, T, i, kb, P, s * _KBLOCK, 0, kn)",
        "outer_4x16(T, i, ja + 16 * s, T, i, kb, P, s * _KBLOCK, 0, kn)",
        (MINPLUS, "-k", "far_product"),
        "the far product's 8-row block (64-byte vectors) updates only its first 4 rows",
    ),
    M(
        "transpose-swaps-two-rows",
        "src/optri/engines/_llvm.py",
        "quad_lo, quad_hi = [0, 1, 2, 3, 8, 9, 10, 11], [4, 5, 6, 7, 12, 13, 14, 15]",
        "quad_lo, quad_hi = [0, 1, 2, 3, 8, 9, 11, 10], [4, 5, 6, 7, 12, 13, 14, 15]",
        (MINPLUS, "-k", "transpose or far_product"),
        "the 8 x 8 transpose puts rows 6 and 7 of the input in each other's place",
    ),
    M(
        "far-pack-forgets-the-tail",
        "src/optri/engines/_minplus.py",
        "for t in range(k8, kn):",
        "for t in range(k8, k8):",
        (MINPLUS, "-k", "far_product or tiling"),
        "splits past the last whole 8 of a block are never copied into the packed B",
    ),
    M(
        "product-8-rows-forgets-columns-past-strips",
        "src/optri/engines/_minplus.py",
        "_product4(T, mask, use_mask, ia, i8, jf, jb, k0, k1)",
        "_product4(T, mask, use_mask, ia, i8, jf, jb, k0, k0)",
        (MINPLUS, "-k", "dense_product"),
        "8-row products leave the columns past the last whole strip without their splits",
    ),
    M(
        "product-8-rows-forgets-rows-past-blocks",
        "src/optri/engines/_minplus.py",
        "_product4(T, mask, use_mask, i8, ib, ja, jb, k0, k1)",
        "_product4(T, mask, use_mask, i8, ib, ja, jb, k0, k0)",
        (MINPLUS, "-k", "dense_product"),
        "8-row products leave the rows past the last whole 8-row block without their splits",
    ),
    M(
        "product-8-rows-mask-checks-4-rows",
        "src/optri/engines/_minplus.py",
        "if _any_allowed(mask, use_mask, i, i + 8, j, j + 16):",
        "if _any_allowed(mask, use_mask, i, i + 4, j, j + 16):",
        (MINPLUS, "-k", "dense_product"),
        "an 8 x 16 block is skipped when only its lower 4 rows hold allowed chords",
    ),
    M(
        "register-block-integer-max",
        "src/optri/engines/_llvm.py",
        'f"llvm.smin.v{lanes}i{8 * size}"',
        'f"llvm.smax.v{lanes}i{8 * size}"',
        (MINPLUS, "-k", "register_block"),
        "the integer path keeps the largest sum",
    ),
    M(
        "edge-row-trusts-tiny-lengths",
        "src/optri/weights.py",
        "inexact += 0 if _SQRT_LO < out[q] < math.inf else 1",
        "inexact += 0 if out[q] < math.inf else 1",
        (MINPLUS, "-k", "edge_weight_row"),
        "lengths whose squares underflow keep the plain formula's wrong value",
    ),
    # --- objective ------------------------------------------------------------------
    M(
        "max-neutral-zero",
        "src/optri/objective.py",
        'vals = tuple(zero if c == "sum" else -math.inf for c in self.components)',
        "vals = tuple(zero for c in self.components)",
        (ENGINES, SIMPLE, "-k", "brute or oracle or negative"),
        'a side counts as 0 under "max": wrong for negative weights (min_angle)',
    ),
    M(
        "lex-combine-all-sum",
        "src/optri/objective.py",
        'fns = tuple(_sum3 if c == "sum" else _max3 for c in self.components)',
        "fns = tuple(_sum3 for c in self.components)",
        (ENGINES, "tests/test_enumerate_kbest.py"),
    ),
    # --- weights --------------------------------------------------------------------
    M(
        "perimeter-drops-a-side",
        "src/optri/weights.py",
        "edge_weight(code, p, k, j) + edge_weight(code, p, i, j)",
        "edge_weight(code, p, k, j)",
        (WEIGHTS, ENGINES),
    ),
    M(
        "diagonal-counts-sides",
        "src/optri/weights.py",
        "return 0.0  # a polygon side is not a diagonal",
        "return 0.5 * d",
        (WEIGHTS, ENGINES),
    ),
    M(
        "max-angle-is-smallest",
        "src/optri/weights.py",
        "return math.acos(min(_cosine(a, b, c), _cosine(b, c, a), _cosine(c, a, b)))",
        "return math.acos(max(_cosine(a, b, c), _cosine(b, c, a), _cosine(c, a, b)))",
        (WEIGHTS,),
    ),
    M(
        "aspect-ratio-inverted",
        "src/optri/weights.py",
        "return a * b * c / (8.0 * q)",
        "return 8.0 * q / (a * b * c)",
        (WEIGHTS,),
    ),
    M(
        "area-3d-drops-z",
        "src/optri/weights.py",
        "return _ldexp(0.5 * math.sqrt(cx * cx + cy * cy + cz * cz), 2 * e)",
        "return _ldexp(0.5 * math.sqrt(cx * cx + cy * cy), 2 * e)",
        (WEIGHTS,),
    ),
    # --- simple polygons: validation and the valid-diagonal masks ---------------------
    M(
        "straight-vertex-is-convex",
        "src/optri/polygon.py",
        "if not (np.all(signs > 0) or np.all(signs < 0)):",
        "if not (np.all(signs >= 0) or np.all(signs <= 0)):",
        (ERRORS, SIMPLE, "-k", "straight"),
    ),
    M(
        "convex-winding-unchecked",
        "src/optri/polygon.py",
        "return int(np.count_nonzero(~upper & following(upper))) == 1",
        "return True",
        (ERRORS, "-k", "invalid_polygons or pentagram or oracle"),
        "a ring around twice taken as convex, so never searched for repeated vertices",
    ),
    M(
        "lowest-takes-rightmost",
        "src/optri/polygon.py",
        "return int(low[np.argmin(points[low, 0])])",
        "return int(low[np.argmax(points[low, 0])])",
        ("src/optri/polygon.py", ERRORS, SIMPLE),
    ),
    M(
        "clockwise-order-wrong",
        "src/optri/polygon.py",
        "order = np.concatenate(([0], np.arange(n - 1, 0, -1))).astype(np.int64)",
        "order = np.arange(n - 1, -1, -1).astype(np.int64)",
        (ENGINES, SIMPLE, "-k", "clockwise"),
    ),
    M(
        "closing-vertex-kept",
        "src/optri/polygon.py",
        "while end > 3 and np.array_equal(ring[0], ring[end - 1]):",
        "while False:",
        (ENGINES,),
    ),
    M(
        "in-cone-reflex-as-convex",
        "src/optri/predicates.py",
        "return np.where(convex, left_of_next & left_of_prev, left_of_next | left_of_prev)",
        "return left_of_next & left_of_prev",
        (MASK,),
    ),
    M(
        "touch-reported-as-cross",
        "src/optri/predicates.py",
        "cross = (o1 * o2 < 0) & (o3 * o4 < 0)",
        "cross = (o1 * o2 <= 0) & (o3 * o4 <= 0)",
        (MASK, "-k", "named or indices"),
    ),
    M(
        "scan-through-vertex",
        "src/optri/simple/_kernels.py",
        "return False  # the chord runs through vertex a",
        "pass  # the chord runs through vertex a",
        (MASK,),
    ),
    M(
        "ear-ignores-vertex-on-new-diagonal",
        "src/optri/simple/_kernels.py",
        "_orient(x[q], y[q], x[p], y[p], x[w], y[w]) >= 0",
        "_orient(x[q], y[q], x[p], y[p], x[w], y[w]) > 0",
        (MASK,),
        "an ear whose cut (q, p) passes through a vertex is clipped anyway",
    ),
    M(
        "count-ignores-mask",
        "src/optri/enumeration/counting.py",
        "ok = usable_chords(polygon)",
        "ok = None",
        ("tests/test_enumerate_counts.py", MASK, "-k", "count or non_convex"),
        "a non-convex polygon counted as convex (Catalan)",
    ),
    # --- enumeration and the matrix chain ----------------------------------------------
    M(
        "kbest-max-led-treated-monotone",
        "src/optri/enumeration/kbest.py",
        'return len(components) == 1 or components[0] == "sum"',
        "return True",
        ("tests/test_enumerate_kbest.py",),
    ),
    M(
        "chain-parens-swapped",
        "src/optri/chain.py",
        'stack.extend([")", (k, b), (a, k), "("])',
        'stack.extend([")", (a, k), (k, b), "("])',
        ("tests/test_core_chain.py",),
    ),
    # --- holes ----------------------------------------------------------------------
    M(
        "patch-wound-backwards",
        "src/optri/holes/mesh.py",
        "return rec, loop.vertices[tri.triangles]",
        "return rec, loop.vertices[tri.triangles[:, ::-1]]",
        (MESH,),
    ),
    M(
        "exact-walk-drops-triangles",
        "src/optri/holes/_exact.py",
        "            if b - a > 1:",
        "            if b - a > 2:",
        (POLYLINE,),
    ),
    M(
        "liepa-area-not-summed",
        "src/optri/holes/liepa.py",
        "return float(worst), float(normals[:, 4].sum())",
        "return float(worst), float(normals[:, 4].max())",
        (POLYLINE,),
    ),
    M(
        "liepa-recurrence-ignores-area",
        "src/optri/holes/_liepa.py",
        "if c1 < best1 or (c1 == best1 and C[1, t] < best2):",
        "if c1 < best1:",
        (POLYLINE,),
    ),
    M(
        "exact-ignores-forbidden-chords",
        "src/optri/holes/_exact.py",
        "            if L == n - 1 or allowed[i, j]:",
        "            if True:",
        ("tests/test_mesh_exact.py", "-k", "textbook or forbidden"),
        "the exact search joins vertices the mesh already joins (an edge with 4 faces)",
    ),
    M(
        "liepa-ignores-forbidden-chords",
        "src/optri/holes/_liepa.py",
        "if not allowed[i, j] and not (i == 0 and j == n - 1):",
        "if False:",
        ("tests/test_mesh_manifold.py", "-k", "existing_edge"),
    ),
    M(
        "delaunay-candidates-keep-forbidden-chords",
        "src/optri/holes/modes.py",
        "tris = tris[_uses_allowed(tris, hole.allowed)]",
        "tris = tris",
        ("tests/test_mesh_manifold.py", "-k", "existing_edge"),
    ),
    M(
        "zero-area-is-just-a-fold",
        "src/optri/holes/_kernels.py",
        "DEGENERATE_KEY = 3.0",
        "DEGENERATE_KEY = 2.0",
        ("tests/test_mesh_manifold.py", "-k", "flat_sheet"),
        "a flat sheet's border gets zero-area faces although patches without them tie",
    ),
    M(
        "pinched-fans-not-followed",
        "src/optri/holes/boundary.py",
        "    if len(many):",
        "    if False:",
        ("tests/test_mesh_manifold.py", "-k", "pinched or two_vertices"),
    ),
    M(
        "mesh-forgets-patch-edges",
        "src/optri/holes/mesh.py",
        "            joined.add(patch)",
        "            pass",
        ("tests/test_mesh_manifold.py", "-k", "two_vertices"),
    ),
    M(
        "exact-bound-prunes-the-optimum",
        "src/optri/holes/_exact.py",
        "                B[first + s] = best if best <= U else np.inf",
        "                B[first + s] = best if best < U else np.inf",
        ("tests/test_mesh_exact.py", "-k", "bound or textbook"),
    ),
    M(
        "loader-merges-with-trimesh",
        "src/optri/io/meshes.py",
        'force="mesh", process=False)',
        'force="mesh", process=True)',
        ("tests/test_mesh_cli.py", "-k", "scale"),
        "trimesh's absolute 1e-8 merge collapses a mesh drawn in nanometres",
    ),
    # --- batch ----------------------------------------------------------------------
    M(
        "resume-redoes-every-part",
        "src/optri/batch/driver.py",
        "if part.exists():",
        "if False:",
        (RESUME,),
    ),
    M(
        "manifest-ignores-weight",
        "src/optri/batch/driver.py",
        '"weight": repr(s.options["weight"]),',
        '"weight": "perimeter",',
        (RESUME,),
    ),
    M(
        "interrupted-write-leaves-temporary",
        "src/optri/io/atomic.py",
        "os.unlink(tmp)",
        "pass",
        (RESUME, ERRORS, "-k", "sigint or atomic"),
    ),
    M(
        "stale-temporaries-kept",
        "src/optri/batch/layout.py",
        'for p in self.parts_dir.glob(".part-*.tmp*"):',
        'for p in self.parts_dir.glob(".none-*.tmp*"):',
        (RESUME,),
    ),
    M(
        "error-reason-multi-line",
        "src/optri/batch/records.py",
        'return " ".join(str(message).split()) or "unknown error"',
        'return str(message) or "unknown error"',
        ("tests/test_batch_badinput.py",),
    ),
    # --- GPU engine: the CUDA weight twin, the kernels (simulator), the PTX checks --------
    M(
        "gpu-twin-min-angle-drops-an-angle",
        "src/optri/engines/_gpu_device.py",
        "return -min(ta, min(tb, tc))",
        "return -min(ta, tb)",
        (TWINS,),
    ),
    M(
        "gpu-twin-diagonal-counts-the-closing-side",
        "src/optri/engines/_gpu_device.py",
        "if hi - lo == 1 or (lo == 0 and hi == n - 1):",
        "if hi - lo == 1:",
        (TWINS,),
    ),
    M(
        "gpu-rebuild-ties-to-largest-k",
        "src/optri/engines/_gpu_kernels.py",
        "(sa[tid] < 0 or oa < sa[tid])",
        "(sa[tid] < 0 or oa > sa[tid])",
        GPU_SIM,
    ),
    M(
        "gpu-finish-ignores-the-mask",
        "src/optri/engines/_gpu_kernels.py",
        "if has_mask and mask[i, j] == 0:",
        "if has_mask and mask[i, j] == 2:",
        GPU_SIM,
    ),
    M(
        "gpu-finish-launch-bounds-of-the-wrong-block",
        "src/optri/engines/_gpu_kernels.py",
        "finish=finish_kernel(tile, finish_threads, dtype),",
        "finish=finish_kernel(tile, threads, dtype),",
        (GPU_PTX,),
    ),
    # --- the top-down trampoline (memo and the naive recursion) ---------------------------
    M(
        "top-down-hits-without-flag",
        "src/optri/engines/recurrence.py",
        "elif hits and watch is not None:",
        "elif watch is not None:",
        (TRACE, "-k", "naive"),
        'the naive recursion reports the polygon sides it is handed as "hit"s',
    ),
    M(
        "top-down-counts-the-root",
        "src/optri/engines/recurrence.py",
        "requests = 0",
        "requests = 1",
        (ENGINES, "-k", "memo_counts"),
        "the root cell counted as a request: lookups and requests off by one",
    ),
    M(
        "top-down-root-call-unseen",
        "src/optri/engines/recurrence.py",
        'watch("call", 0, root, None, None)',
        "pass",
        (TRACE, "-k", "counts"),
        "the observer never hears the root call",
    ),
    M(
        "memo-never-looks-up",
        "src/optri/engines/memo.py",
        "rec.top_down(lambda p, q: cost[p][q], store, hits=True)",
        "rec.top_down(lambda p, q: cost[p][q] if q - p == 1 else None, store, hits=True)",
        (ENGINES, "-k", "memo_counts"),
        "memo recomputes every sub-polygon (the naive recursion under memo's name)",
    ),
    # --- exact predicates: the float filter and the exact stages ------------------------
    M(
        "orient-exact-stage-skipped",
        "src/optri/predicates.py",
        "    if todo.any():",
        "    if False:",
        (PREDICATES, "-k", "fractions"),
        "turns the float filter cannot certify come out collinear",
    ),
    M(
        "orient-filter-too-small",
        "src/optri/predicates.py",
        "bound = np.maximum(ORIENT_FILTER * (np.abs(left) + np.abs(right)), _FILTER_FLOOR)",
        "bound = np.maximum(_EPS * (np.abs(left) + np.abs(right)), _FILTER_FLOOR)",
        (PREDICATES, "-k", "fractions or filter"),
        "the vectorized filter trusts float determinants a third of its error bound",
    ),
    M(
        "orient-sign-trusts-the-float",
        "src/optri/predicates.py",
        "    return orient_exact(ax, ay, bx, by, cx, cy)",
        "    return 1 if det > 0 else -1 if det < 0 else 0",
        (PREDICATES, "-k", "compiled"),
        "the scalar (compiled) orient_sign skips its exact stage",
    ),
    M(
        "exact-rows-trust-rounded-differences",
        "src/optri/predicates.py",
        "exact = (top - low <= _SPREAD) & ~ut.any(axis=1) & ~vt.any(axis=1)",
        "exact = top - low <= _SPREAD",
        (PREDICATES, "-k", "fractions"),
        "the two-product shortcut taken when a coordinate difference was rounded",
    ),
    # --- polygons with holes: the program, the reductions, the labels, the bounds -------
    M(
        "domain-diagonal-balance-loose",
        "src/optri/domains/program.py",
        "lo = np.concatenate((np.ones(nf), np.zeros(nd), np.zeros(len(cu))))\n"
        "    hi = np.concatenate((np.ones(nf), np.zeros(nd), np.ones(len(cu))))",
        "lo = np.concatenate((np.ones(nf), -np.ones(nd), np.zeros(len(cu))))\n"
        "    hi = np.concatenate((np.ones(nf), np.ones(nd), np.ones(len(cu))))",
        (DOM_BRUTE, "-k", "every_sum_weight"),
        # loosened one way only (lo or hi alone) the mutant is equivalent: an uncovered
        # region's boundary diagonals, sorted (a < b), never all have it on the same side
        "a free diagonal may be used on one side only: the triangles need not tile",
    ),
    M(
        "forced-diagonals-include-crossed",
        "src/optri/domains/reduce.py",
        "forced[alive[greedy[~crossed]]] = True",
        "forced[alive[greedy]] = True",
        (DOM_BRUTE, "-k", "every_sum_weight"),
        "every diagonal of one greedy triangulation is fixed, crossed ones too",
    ),
    M(
        "domain-gate-excludes-bottleneck",
        "src/optri/domains/solver.py",
        "keep = keep & (setup.values[:, c] <= found.value)",
        "keep = keep & (setup.values[:, c] < found.value)",
        (DOM_BRUTE, "-k", "lexicographic"),
        "the second phase of (max, sum) forbids the bottleneck triangle itself",
    ),
    M(
        "domain-proven-if-any-block-is",
        "src/optri/domains/search.py",
        "proven = all(f.proven for f in found) or _meets(value, bound)",
        "proven = any(f.proven for f in found) or _meets(value, bound)",
        (DOM_INV, "-k", "time_limit"),
        "a time-limited search labelled proven because one block (a DP block) is",
    ),
    M(
        "max-bisection-cut-short-is-proven",
        "src/optri/domains/search.py",
        "    if lo >= hi:\n        return Found(best, value, value, True)",
        "    if True:\n        return Found(best, value, value, True)",
        (DOM_INV, "-k", "time_limited_max"),
        "a bisection stopped by the time limit reports its incumbent as proven",
    ),
    M(
        "sum-floor-ears-counted-whole",
        "src/optri/domains/bounds.py",
        "share = np.where(k > 0, (w - m) / np.maximum(k, 1), np.inf)",
        "share = np.where(k > 0, w - m, np.inf)",
        (DOM_BRUTE, "-k", "floor"),
        "an ear's weight is counted once per fixed side: the 'bound' exceeds the optimum",
    ),
    M(
        "max-bound-from-the-top-level",
        "src/optri/domains/search.py",
        "return Found(best, value, float(levels[lo]), False)",
        "return Found(best, value, float(levels[hi - 1]), False)",
        (DOM_INV, DOM_BRUTE, "-k", "time_limited_max"),
        "a cut-short bisection claims the highest level below its incumbent as its bound",
    ),
    M(
        "check-domain-allows-double-cover",
        "src/optri/result.py",
        '_require(count == 1, f"edge {(a, b)} used {count} times in the same direction")',
        '_require(count >= 1, f"edge {(a, b)} used {count} times in the same direction")',
        (DOM_INV, "-k", "check_catches"),
    ),
    M(
        "check-domain-ignores-unmatched",
        "src/optri/result.py",
        '_require((b, a) in used and (b, a) not in inner, f"edge {(a, b)} unmatched")',
        '_require(True, f"edge {(a, b)} unmatched")',
        (DOM_INV, "-k", "check_catches"),
    ),
    M(
        "check-domain-ignores-cost",
        "src/optri/result.py",
        "\n        self._check_areas(rtol)\n        if self._recompute is not None:\n"
        "            again = self._recompute(self.triangles)\n"
        "            _require(_close(again, self.weight, rtol),",
        "\n        self._check_areas(rtol)\n        if self._recompute is not None:\n"
        "            again = self._recompute(self.triangles)\n"
        "            _require(True,",
        (DOM_INV, "-k", "check_catches"),
    ),
    # --- batch: polygons with holes -------------------------------------------------------
    M(
        "batch-pair-drops-last-hole",
        "src/optri/batch/each.py",
        "return rings[0], rings[1:]",
        "return rings[0], rings[1:-1]",
        (BATCH_HOLES, "-k", "ring_pairs"),
    ),
    M(
        "batch-keeps-first-hole-only",
        "src/optri/batch/solver.py",
        "for k, ring in enumerate(rings):",
        "for k, ring in enumerate(rings[:2]):",
        (BATCH_HOLES, "-k", "ring_pairs or holes"),
        "a polygon's second and later holes are dropped",
    ),
    M(
        "batch-shapely-rings-out-of-order",
        "src/optri/batch/solver.py",
        "rings = [geom.exterior, *geom.interiors]",
        "rings = [*geom.interiors, geom.exterior]",
        (BATCH_HOLES, "-k", "ring_pairs or holes"),
        "a shapely polygon's exterior numbered after its holes",
    ),
    M(
        "batch-projection-forgets-rings",
        "src/optri/batch/solver.py",
        "arrays.append(arr.with_vertices(project(arr.vertices)))",
        "arrays.append(project(arr.vertices))",
        (BATCH_HOLES, "tests/test_batch_gis.py", "-k", "ring_pairs or holes or project"),
        "a projected polygon with holes is solved as one ring of all its vertices",
    ),
    M(
        "tile-not-mirrored",
        "src/optri/engines/_minplus.py",
        "        _far(T, P, mask, _ROWS, i0, i1, j0, j1, i1, j0)\n    if d > 0:\n"
        "        _square(T, ew, mask, use_mask, i0, i1, j0, j1)\n    _mirror(T, i0, i1, j0, j1)\n",
        "        _far(T, P, mask, _ROWS, i0, i1, j0, j1, i1, j0)\n    if d > 0:\n"
        "        _square(T, ew, mask, use_mask, i0, i1, j0, j1)\n",
        (MINPLUS, "-k", "both_halves"),
        "a finished tile is not copied below the diagonal, where the far products and the "
        "trace read it",
    ),
    M(
        "mirror-skips-the-sides",
        "src/optri/engines/_minplus.py",
        "for c in range(max(j, r + 1), min(j + 8, j1)):",
        "for c in range(max(j, r + 2), min(j + 8, j1)):",
        (MINPLUS, "-k", "both_halves"),
        "cells next to the diagonal (the polygon's sides) are not copied below it",
    ),
    M(
        "edge-cell-reads-the-mirror",
        "src/optri/engines/_minplus.py",
        "best = fmin(best, T[i, k] + T[k, j])",
        "best = fmin(best, T[i, k] + T[j, k])",
        (MINPLUS, "-k", "both_halves"),
        "cells at the edges of blocks read the lower half before their tile is copied there",
    ),
    M(
        "paired-tile-forgets-the-lower-rows",
        "src/optri/engines/_minplus.py",
        "        _far(T, P, mask, _ROWS, i0, i1, j0, j1, i1, i1 + tile)\n",
        "",
        (MINPLUS, "-k", "python_table"),
        "the upper tile of a pair skips the splits through the lower tile's rows",
    ),
    M(
        "paired-tile-forgets-the-last-column-tile",
        "src/optri/engines/_minplus.py",
        "i1, i1 + tile)\n        _far(T, P, mask, _ROWS, i0, i1, j0, j1, j0 - tile, j0)\n",
        "i1, i1 + tile)\n",
        (MINPLUS, "-k", "python_table"),
        "the upper tile of a pair skips the splits its partner could not share",
    ),
    M(
        "call-reinitializes-its-first-diagonal",
        "src/optri/engines/_minplus.py",
        "    taken = np.zeros(1, dtype=np.int64)\n",
        "    taken = np.zeros(1, dtype=np.int64)\n"
        "    for t in range(nt - d0):\n"
        "        if d0 > 0:\n"
        "            _fill_inf(T, t * tile, min(T.shape[0], t * tile + tile), (t + d0) * tile,"
        " min(T.shape[0], (t + d0) * tile + tile))\n",
        (MINPLUS, "-k", "one_tile_diagonal"),
        "a kernel call wipes the far splits its first diagonal got from the previous call",
    ),
    M(
        "pairs-start-a-diagonal-early",
        "src/optri/engines/_minplus.py",
        "elif d % 2 == 1 and d >= 5:",
        "elif d % 2 == 1 and d >= 3:",
        (MINPLUS, "-k", "python_table"),
        "a tile on diagonal 3 assumes a partner that applied no splits for it",
    ),
    M(
        "meminfo-read-as-bytes",
        "src/optri/engines/memory.py",
        "return None if kib is None else kib * 1024",
        "return kib",
        ("tests/test_bad_inputs.py", "-k", "meminfo"),
        "MemAvailable taken in bytes where /proc/meminfo gives kB: a 1024x smaller ceiling",
    ),
    M(
        "fill-ignores-stop",
        "src/optri/engines/_minplus.py",
        "        while load_acquire(stop, 0) == 0:",
        "        while True:",
        ("tests/test_fast_engine.py", "-k", "watched"),
        "the min-plus fill goes on after Ctrl-C",
    ),
    M(
        "watch-stops-without-waiting",
        "src/optri/engines/jit.py",
        "        stop[0] = 1\n        helper.join()\n",
        "        stop[0] = 1\n",
        ("tests/test_fast_engine.py", "-k", "watched"),
        "Ctrl-C returns while the helper thread still fills the table",
    ),
    M(
        "watch-never-stops",
        "src/optri/engines/jit.py",
        "        stop[0] = 1\n",
        "        pass\n",
        ("tests/test_fast_engine.py", "-k", "watched"),
        "Ctrl-C waits for the whole fill",
    ),
    M(
        "watched-progress-counts-one-tile-less",
        "src/optri/engines/jit.py",
        "    cells[np.arange(nt - 1), np.arange(1, nt)] -= 1",
        "    cells[np.arange(nt - 1), np.arange(1, nt)] -= 2",
        ("tests/test_fast_engine.py", "-k", "watched"),
        "progress counts miss cells",
    ),
    M(
        "memory-check-floor-ignores-limit",
        "src/optri/engines/memory.py",
        "if nbytes < config.MEMORY_CHECK_MIN_BYTES and config.MEMORY_LIMIT_BYTES is None:",
        "if nbytes < config.MEMORY_CHECK_MIN_BYTES:",
        ("tests/test_bad_inputs.py", "-k", "memory"),
        "an explicit MEMORY_LIMIT_BYTES not applied to small requests",
    ),
    M(
        "following-wraps-the-wrong-end",
        "src/optri/predicates.py",
        "    return np.concatenate((a[1:], a[:1]))",
        "    return np.concatenate((a[1:], a[-1:]))",
        (PREDICATES, "-k", "following"),
        "the last vertex's successor is itself, not the first vertex",
    ),
]
