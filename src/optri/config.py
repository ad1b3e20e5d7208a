"""Every tunable of optri in one place: memory ceiling, thresholds, tile sizes, limits.

Values are plain module attributes so tests and callers can patch them
(``optri.config.BRUTE_MAX_N = 10``); :func:`reset` restores the defaults.

>>> from optri import config
>>> config.BRUTE_MAX_N = 9
>>> config.reset(); config.BRUTE_MAX_N
13
"""

from __future__ import annotations

__all__ = ["reset"]

#: Fraction of the memory available to the process (the least of /proc/meminfo's
#: MemAvailable and the room its cgroup v1/v2 limits leave) an allocation may take.
MEMORY_FRACTION = 0.8
#: Hard override of the memory ceiling in bytes (None: ask the OS).
MEMORY_LIMIT_BYTES: int | None = None
#: Allocations smaller than this are not checked against the OS's counters (reading them
#: costs 20-80 us, a tenth of a small polygon's solve): Python and numpy already
#: take several times as much. ``MEMORY_LIMIT_BYTES``, when set, is checked at every size.
MEMORY_CHECK_MIN_BYTES = 32 << 20
#: A table of the compiled engine this large or larger is kept this many seconds after
#: its solve (its pages lazily freed: the kernel takes them back when it needs memory),
#: for the next solve to reuse instead of fresh pages, which the kernel must zero (a few
#: per cent of a large solve; docs/performance-log.md). 0 turns it off. Smaller tables come from
#: the C library, which reuses their memory anyway.
TABLE_CACHE_SECONDS = 1.0
TABLE_CACHE_MIN_BYTES = 32 << 20
#: Largest n the brute-force oracle accepts (Catalan(n-2) triangulations).
BRUTE_MAX_N = 13
#: 3-D input counts as planar (then triangulated as a simple polygon in its own plane) when
#: every vertex lies within this fraction of its extent from the plane. Every 2-D sign
#: (collinear, convex, crossing, inside) is exact and needs no tolerance.
PLANARITY_RTOL = 1e-9
#: The un-memoized recursion (``method="naive"``, :func:`optri.trace`) makes 3^(n-2) calls
#: on an n-gon (59,049 at 12, about 3 events each when traced); it refuses larger polygons.
NAIVE_MAX_N = 12
#: :func:`optri.trace` keeps every event (about 4 C(n, 3) of them for memo: 1.1 million at
#: 120); it refuses larger polygons.
TRACE_MAX_N = 120
#: The explorer page (``optri explore``, notebook reprs of a trace) embeds the C(n, 3)
#: triangle weights and reruns the DP in the browser; it refuses larger polygons, whose
#: table no longer fits a screen.
EXPLORE_MAX_N = 40
#: ``Trace.animate`` draws each frame with matplotlib (about 0.1 s each); it refuses more.
ANIMATE_MAX_FRAMES = 1500
#: Notebook HTML (``Triangulation._repr_html_``) shows the n x n table up to this n.
HTML_TABLE_MAX_N = 24
#: ``count_triangulations(n)`` computes Catalan(n - 2) exactly (about 0.6 n digits: a second
#: at n = 100,000, a minute at 1,000,000); it refuses larger n.
COUNT_MAX_N = 200_000
#: k-best for objectives led by "max" (not monotone) enumerates every triangulation;
#: it refuses polygons with more triangulations than this.
KBEST_ENUMERATION_LIMIT = 2_000_000
#: 3-D holes: ``method="auto"`` runs the exact Liepa search up to this many vertices
#: (O(n^4) time at worst, pruned by Liepa's patch; about 8 n^3 / 3 bytes), Liepa's O(n^3)
#: recurrence above. Measured by benchmarks/bench_mesh.py: see docs/mesh.md.
HOLES_EXACT_MAX_N = 400
#: 3-D holes, ``fill_holes(refine=True)``: ``method="auto"`` starts the refinement from the
#: exact patch up to this many boundary edges, and above it from Liepa's recurrence over
#: Delaunay candidates (as CGAL does): refinement and fairing then decide the surface, and
#: the refined patches were as close to the true surface either way, at a small part of the
#: exact search's time; below it, computing the candidates costs more than the search.
#: Measured by benchmarks/bench_refill.py: see docs/mesh.md.
HOLES_REFINE_EXACT_MAX_N = 64
#: 3-D holes: work (about apex evaluations) per compiled-kernel call of the Liepa and
#: exact searches; between calls Ctrl-C takes effect.
HOLES_CHUNK_WORK = 2e7
#: Mesh files: vertices closer than this fraction of the bounding-box diagonal are merged
#: on loading (0: only exactly equal positions, at any scale).
MESH_MERGE_RTOL = 0.0
#: Batch: work per chunk, in units of one weight evaluation (about a microsecond in Python).
BATCH_CHUNK_WORK = 400_000
#: Batch: the same for chunks of an Arrow layer solved as columns by the compiled kernel,
#: whose weight evaluations cost a few nanoseconds: larger chunks, fewer parts and tasks.
BATCH_COMPILED_CHUNK_WORK = 20_000_000
#: Batch: fixed per-polygon work (validation, result building) in the same units.
BATCH_POLYGON_WORK = 600
#: Batch: chunk size bounds, and how many polygons are sampled to pick a size.
BATCH_CHUNK_MIN = 8
BATCH_CHUNK_MAX = 2000
BATCH_CHUNK_SAMPLE = 256
#: Arrow layers (GeoParquet, GeoPackage, FlatGeobuf, shapefile) into table outputs are
#: solved as columns, a chunk at a time (optri.batch.chunks); False: feature by feature.
BATCH_COLUMNAR = True
#: On the local pool, workers read their chunk's rows from the layer, solve them and write
#: the part themselves (optri.batch.partwork); False: the parent reads and writes.
BATCH_WORKERS_READ = True
#: A single GeoParquet output is joined from its parts while later parts are still solved
#: (optri.batch.tablefiles.PartJoiner); False: all at once after the last part.
BATCH_JOIN_WHILE_SOLVING = True
#: A single GeoParquet output's row groups: parts are held until they reach this many
#: rows or Arrow bytes, then written as one row group. A part per row group would make
#: thousands of small groups, whose footer entries the writer keeps in memory to the
#: end (some 13 kB each: 65 MB at 10M footprints) and readers scan one by one.
BATCH_ROW_GROUP_ROWS = 65_536
BATCH_ROW_GROUP_BYTES = 16 << 20
#: Batch: id hashes (8 bytes each) the parent keeps in memory to find duplicate ids; beyond
#: this many they go to temporary bucket files, so the parent's memory stays flat with rows.
BATCH_ID_HASHES_IN_MEMORY = 1 << 21
#: Batch: chunks in flight per worker (keeps workers busy without reading ahead far).
BATCH_IN_FLIGHT_PER_WORKER = 2
#: Batch: rows per Parquet record batch / GeoPackage page while reading.
BATCH_ROWS_PER_READ = 4096
#: Batch: bytes read at a time by the streaming GeoJSON parser.
BATCH_READ_BLOCK = 1 << 20
#: Batch: deepest nesting of JSON attribute values kept (deeper values make an error record).
BATCH_MAX_JSON_DEPTH = 64
#: Batch: seconds between checks that the parent still lives, in workers without pidfd.
BATCH_WATCHDOG_SECONDS = 0.5
#: Many small polygons (triangulate_many, batch): the compiled path takes polygons of up
#: to this many vertices in one kernel call per chunk; larger ones (and every polygon when
#: False) go to ``optri.triangulate`` one by one, whose engine parallelizes inside them.
MANY_MAX_N = 256
#: Many small polygons: the compiled path is used at all (False: always polygon by polygon).
MANY_COMPILED = True
#: Many small polygons: polygons per kernel call (bounds the ragged arrays' memory).
MANY_KERNEL_CHUNK = 8192
#: CLI: seconds a run takes before its progress bar appears (on a terminal, any input size).
CLI_PROGRESS_DELAY = 1.0
#: CLI: ``optri solve --table`` prints the n x n table up to this n and refuses larger
#: polygons before solving: its lower cells list every split, so the text grows as n^3
#: (about 80 KB at 30, 98 MB at 300). From Python: ``triangulate(..., keep_table=True)``.
CLI_TABLE_MAX_N = 30
#: method="auto" picks the GPU engine (when a GPU is present) from this many vertices on:
#: a process's first GPU solve compiles its kernels (seconds), which pays off only where
#: the compiled CPU engine takes about as long. An estimate (docs/performance-log.md);
#: retune with benchmarks/bench_gpu.py.
GPU_AUTO_MIN_N = 8000
#: Side of the square table tiles the GPU engine works on (shared-memory blocking).
GPU_TILE = 64
#: Depth of the k-slices of a tile product staged in shared memory at a time.
GPU_K_CHUNK = 16
#: Threads per block of the GPU kernels (tests patch it low).
GPU_THREADS_PER_BLOCK = 256
#: Split the k-range of a tile product until a launch has this many blocks (fills the GPU
#: on the last tile diagonals, where few tiles remain).
GPU_MIN_BLOCKS = 528
#: Most blocks in one launch; grid-stride loops cover the rest.
GPU_MAX_BLOCKS = 65535
#: Fraction of the free device memory the GPU engine may take.
GPU_MEMORY_FRACTION = 0.9
#: Hard override of the device memory ceiling in bytes (None: ask the device).
GPU_MEMORY_LIMIT_BYTES: int | None = None
#: ``method="auto"`` leaves smaller problems to the Python engines, whose results small
#: polygons have always had (the min-plus table's sums can differ in the last bit).
FAST_AUTO_MIN_N = 120
#: Compiled engine: below this n the min-plus fill runs on one thread. A parallel region
#: ends when every thread has finished, which on a busy machine waits for a descheduled
#: worker's next time slice: below this size that wait costs more than a second thread
#: saves (docs/performance-log.md).
FAST_PARALLEL_MIN_N = 1000
#: The same for the generic kernel (any weight), whose splits cost ~20x more each.
FAST_GENERIC_PARALLEL_MIN_N = 250
#: Compiled engine: side of the square tiles of cells of the min-plus kernel; None: 64
#: below 800 vertices, 128 below 4000, 256 from there (a tile's far splits read and copy
#: 2 x tile rows per split block: a larger tile does more work per byte from memory and per
#: value copied, but leaves more of the work to the near splits; measurements in
#: ``optri.engines.jit.minplus_tile``).
FAST_TILE: int | None = None
#: Compiled engine: tile side of the generic kernel (any weight): compute-bound, so small
#: tiles, which keep each tile-diagonal short (Ctrl-C stops the fill between them), cost
#: nothing.
FAST_GENERIC_TILE = 16
#: Compiled engine: fills of more min-plus steps than this (n^3 / 6, a weight evaluation
#: of the generic kernel counting 20; about 0.1 s) run in a helper thread while the
#: calling thread reports progress and takes Ctrl-C, which stops the fill at its next tile
#: (generic kernel: tile-diagonal); shorter fills run in the calling thread.
FAST_WATCH_WORK = 2e9
#: Simple polygons: from this many vertices the chord mask (ear clipping, then a
#: visibility walk from every vertex, on every thread) runs in a helper thread, so
#: that Ctrl-C takes effect at the next ear or walk; below it, on the calling thread alone.
MASK_WATCH_MIN_N = 2000
#: Compiled engine: seconds between progress reports of a watched fill.
FAST_PROGRESS_SECONDS = 0.1

#: Polygons with holes: default ``time_limit`` of the search in seconds (None: no limit).
DOMAIN_TIME_LIMIT: float | None = None
#: Polygons with holes: the least time given to one solver call, even past the limit
#: (HiGHS needs a positive limit; this bounds how far a run can overshoot it per call).
DOMAIN_MIN_SOLVER_SECONDS = 0.05

#: Polygons with holes: a heuristic answer within this relative distance of its proven
#: lower bound counts as proven (the solver's own optimality tolerance is about 1e-9).
DOMAIN_PROVEN_RTOL = 1e-9

#: Polygons with holes: the integer program's costs are scaled (by a power of two) so the
#: largest is near ``2**DOMAIN_COST_EXPONENT``: HiGHS's absolute tolerances (1e-7, 1e-6)
#: then lie far below ``DOMAIN_PROVEN_RTOL`` of the optimum, at every scale of the input.
DOMAIN_COST_EXPONENT = 20

#: A GeoPackage/FlatGeobuf write that fails with less free space than this on its disk is
#: reported as a full disk (GDAL's own message seldom says so).
BATCH_FULL_DISK_BYTES = 16 * 2**20

#: Dask: how often the scheduler reruns a task whose worker died before it gives up
#: (KilledWorker); optri then retries the chunk alone, then polygon by polygon.
BATCH_WORKER_RETRIES = 0

#: Batch: an Arrow layer whose polygons the compiled kernel solves as columns, on at most
#: this many workers, runs them as threads of the calling process (the local pool, and a
#: Dask LocalCluster made for the run): no worker process to start or import in, nothing
#: pickled (feature-by-feature input, JSON, holds the GIL: it keeps processes). A worker
#: thread holds the GIL about a sixth of its time (the kernel, Arrow and shapely release
#: it), so four share one interpreter without queueing much. Beyond four, and for Python
#: weights (which hold the GIL, and may take their process down), each worker is a
#: process of its own.
BATCH_THREADS = 4

#: Dask: how often a wait checks that the cluster still has workers, and how long it may
#: have none before the run stops with an error (a run never hangs on a dead cluster).
BATCH_DASK_POLL_SECONDS = 5.0
BATCH_DASK_NO_WORKER_SECONDS = 120.0

#: The most bytes read from standard input (``-``); ``$OPTRI_MAX_INPUT_BYTES`` overrides it.
MAX_INPUT_BYTES = 2**30

_DEFAULTS = {k: v for k, v in dict(globals()).items() if k.isupper()}


def reset() -> None:
    """Restore every tunable to its default value."""
    globals().update(_DEFAULTS)
