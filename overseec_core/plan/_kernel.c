/*
 * overseec planner kernel: 8- or 16-connected shortest paths on a float32 costmap.
 *
 * Why by hand: no maintained library does "mean of the two cells' costs x step length in metres"
 * on non-square pixels with a reusable workspace; scikit-image's MCP_Geometric has the rule but
 * allocates float64 copies and a traceback array per query (~25 bytes/pixel) and runs a binary
 * heap, dijkstra3d charges the destination voxel only. Python drives everything else (see
 * overseec_core/plan/planner.py); this file is the hot loop only.
 *
 * State per pixel: dist (float64, 8 bytes) and one state byte: bits 0-2 = direction the cell was
 * reached by, bit 3 = has a parent, bit 4 = the direction is a knight move (8 + bits 0-2),
 * bit 7 = settled. Lethal cells are +inf and nodata cells NaN
 * in the float32 cost grid itself, so impassability costs no extra memory. "Unvisited" is the
 * double whose eight bytes are all 0x7F (about 1.38e306), so resets are byte fills (reset()).
 *
 * Two priority queues, both reused between queries (buckets keep their capacity):
 *  - A bucket ring (Dial's algorithm with real keys) when every step costs at least `width` > 0
 *    (the base cost per metre guarantees it): keys within one bucket differ by less than any
 *    step, so no cell in the lowest bucket can improve another and they may be settled in any
 *    order -- the result is exact. Push and pop are O(1); entries are 4-byte cell indices
 *    (a cell pushed twice is settled once; the state byte skips the stale copy). The search is
 *    bound by memory latency, so that freedom is used for locality: a bucket is ordered by
 *    memory block when it is entered (sort_desc) and the cells a few pops ahead are prefetched
 *    (search_loop). bench/bench_plan.py, 10,000² corner to corner, CPU time: 17.0 s before
 *    these changes, 9.9 s after (same costs; among equal-cost routes another may be chosen).
 *  - A radix heap over the IEEE-754 bit patterns of non-negative doubles (monotone as unsigned
 *    integers) otherwise, with A*: Dijkstra and A* with a consistent heuristic extract keys in
 *    non-decreasing order, which is all a radix heap needs; a key that rounding puts a few ulps
 *    below the last extracted one is clamped to it.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "_portable.h" /* the only compiler-specific spellings: forced inlining, clz64 */

#define ST_DIR 0x07u
#define ST_HAS 0x08u
#define ST_DONE 0x80u
#define CANCEL_EVERY 0x3FFF
/* Most buckets in the ring; the planner reads it as _kernel.MAX_RING and uses the radix heap for
   any costmap that would need more. Each bucket costs a Slot plus, once used, a 256-entry buffer
   (~1 KiB), and every query clears all of them: on a 1000 x 1000 costmap the ring beats the
   radix heap with A* up to ~30,000 buckets (28 MiB) and loses beyond (118,000 buckets: 2x slower,
   118 MiB; 471,000: 5x, 448 MiB). The source of truth: planner.py does not repeat it. */
#define MAX_RING 65536

/* ------------------------------------------------------------------------------------------ */
/* Radix heap                                                                                  */
/* ------------------------------------------------------------------------------------------ */

/* Packed to 12 bytes (16 with padding): the queue can hold many entries per frontier cell.
   #pragma pack is understood by MSVC, gcc and clang alike; members are only read and written
   through the struct (never by pointer), so the compiler emits the unaligned accesses itself. */
#pragma pack(push, 1)
typedef struct {
    uint64_t key;
    uint32_t idx;
} Item;
#pragma pack(pop)
typedef char item_is_12_bytes[sizeof(Item) == 12 ? 1 : -1];

typedef struct {
    Item *v;
    size_t n, cap;
} Bucket;

typedef struct {
    uint32_t *v;
    size_t n, cap;
} Slot; /* one bucket of the ring */

typedef struct {
    Bucket b[65];
    uint64_t last;
    size_t size;
    Slot *ring; /* ring buckets, ring_len allocated */
    size_t ring_len;
    uint32_t *tmp; /* scratch of the bucket sort, tmp_cap entries */
    size_t tmp_cap;
} Workspace;

static inline uint64_t key_bits(double x) {
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static inline int bucket_of(uint64_t key, uint64_t last) {
    return key == last ? 0 : 64 - clz64(key ^ last);
}

static void heap_clear(Workspace *h) {
    for (int i = 0; i < 65; i++) h->b[i].n = 0;
    h->last = 0;
    h->size = 0;
}

static int bucket_push(Bucket *bk, uint64_t key, uint32_t idx) {
    if (bk->n == bk->cap) {
        size_t cap = bk->cap ? bk->cap * 2 : 256;
        Item *v = (Item *)realloc(bk->v, cap * sizeof(Item));
        if (!v) return -1;
        bk->v = v;
        bk->cap = cap;
    }
    bk->v[bk->n].key = key;
    bk->v[bk->n].idx = idx;
    bk->n++;
    return 0;
}

static inline int heap_push(Workspace *h, double keyd, uint32_t idx) {
    uint64_t key = key_bits(keyd);
    if (key < h->last) key = h->last; /* rounding below the last extracted key: clamp */
    if (bucket_push(&h->b[bucket_of(key, h->last)], key, idx)) return -1;
    h->size++;
    return 0;
}

/* Pops one item with the smallest key into *out; the heap must not be empty. Returns -1 when
   memory runs out while redistributing (the search is then abandoned with MemoryError). */
static inline int heap_pop(Workspace *h, uint32_t *out) {
    Bucket *b0 = &h->b[0];
    if (b0->n == 0) {
        int i = 1;
        while (h->b[i].n == 0) i++;
        Bucket *bk = &h->b[i];
        uint64_t mn = bk->v[0].key;
        for (size_t j = 1; j < bk->n; j++)
            if (bk->v[j].key < mn) mn = bk->v[j].key;
        h->last = mn;
        for (size_t j = 0; j < bk->n; j++) /* every item lands in a strictly lower bucket */
            if (bucket_push(&h->b[bucket_of(bk->v[j].key, mn)], bk->v[j].key, bk->v[j].idx))
                return -1;
        bk->n = 0;
    }
    h->size--;
    *out = b0->v[--b0->n].idx;
    return 0;
}

/* ------------------------------------------------------------------------------------------ */
/* Bucket ring                                                                                 */
/* ------------------------------------------------------------------------------------------ */

static int ring_prepare(Workspace *h, size_t len) {
    if (len > h->ring_len) {
        Slot *r = (Slot *)realloc(h->ring, len * sizeof(Slot));
        if (!r) return -1;
        memset(r + h->ring_len, 0, (len - h->ring_len) * sizeof(Slot));
        h->ring = r;
        h->ring_len = len;
    }
    for (size_t i = 0; i < h->ring_len; i++) h->ring[i].n = 0;
    return 0;
}

static inline int slot_push(Slot *s, uint32_t idx) {
    if (s->n == s->cap) {
        size_t cap = s->cap ? s->cap * 2 : 256;
        uint32_t *v = (uint32_t *)realloc(s->v, cap * sizeof(uint32_t));
        if (!v) return -1;
        s->v = v;
        s->cap = cap;
    }
    s->v[s->n++] = idx;
    return 0;
}

/* Orders v[0..n) by descending block of memory (so popping from the end visits the cells in
   ascending memory order, one block of about N / 2048 cells -- a few rows -- after the other):
   one counting-sort pass on the top SORT_BITS bits of the largest index; within a block the
   order is left as it is (a bucket's cells may be settled in any order). A full sort measured
   slower: its three passes cost more than the locality they add. Returns -1 when the scratch
   buffer cannot grow. */
#define SORT_BITS 14
static int sort_desc(Workspace *h, uint32_t *v, size_t n) {
    if (n < 64) return 0;
    if (n > h->tmp_cap) {
        size_t cap = n * 2;
        uint32_t *t = (uint32_t *)realloc(h->tmp, cap * sizeof(uint32_t));
        if (!t) return -1;
        h->tmp = t;
        h->tmp_cap = cap;
    }
    uint32_t mx = 0;
    for (size_t i = 0; i < n; i++)
        if (v[i] > mx) mx = v[i];
    int bits = 6; /* about as many blocks as entries, at most 2^SORT_BITS */
    while (bits < SORT_BITS && ((size_t)1 << bits) < n) bits++;
    int shift = 0;
    while ((mx >> shift) >= (1u << bits)) shift++;
    const uint32_t m = (1u << bits) - 1;
    size_t count[1u << SORT_BITS];
    memset(count, 0, (m + 1) * sizeof(size_t));
    for (size_t i = 0; i < n; i++) count[m - (v[i] >> shift)]++; /* descending */
    size_t sum = 0;
    for (size_t d = 0; d <= m; d++) {
        size_t c = count[d];
        count[d] = sum;
        sum += c;
    }
    uint32_t *t = h->tmp;
    for (size_t i = 0; i < n; i++) t[count[m - (v[i] >> shift)]++] = v[i];
    memcpy(v, t, n * sizeof(uint32_t));
    return 0;
}

static void workspace_free(Workspace *h) {
    free(h->tmp);
    for (int i = 0; i < 65; i++) free(h->b[i].v);
    for (size_t i = 0; i < h->ring_len; i++) free(h->ring[i].v);
    free(h->ring);
    free(h);
}

static size_t workspace_bytes(const Workspace *h) {
    size_t s = sizeof(Workspace) + h->tmp_cap * sizeof(uint32_t);
    for (int i = 0; i < 65; i++) s += h->b[i].cap * sizeof(Item);
    for (size_t i = 0; i < h->ring_len; i++) s += sizeof(Slot) + h->ring[i].cap * sizeof(uint32_t);
    return s;
}

static const char *CAPSULE_NAME = "overseec.plan.workspace";

static void workspace_destroy(PyObject *cap) {
    Workspace *h = (Workspace *)PyCapsule_GetPointer(cap, CAPSULE_NAME);
    if (h) workspace_free(h);
}

static PyObject *py_workspace(PyObject *self, PyObject *args) {
    (void)self;
    (void)args;
    Workspace *h = (Workspace *)calloc(1, sizeof(Workspace));
    if (!h) return PyErr_NoMemory();
    PyObject *cap = PyCapsule_New(h, CAPSULE_NAME, workspace_destroy);
    if (!cap) free(h);
    return cap;
}

static PyObject *py_workspace_bytes(PyObject *self, PyObject *args) {
    (void)self;
    PyObject *cap;
    if (!PyArg_ParseTuple(args, "O", &cap)) return NULL;
    Workspace *h = (Workspace *)PyCapsule_GetPointer(cap, CAPSULE_NAME);
    if (!h) return NULL;
    return PyLong_FromSize_t(workspace_bytes(h));
}

/* ------------------------------------------------------------------------------------------ */
/* Argument checks                                                                            */
/* ------------------------------------------------------------------------------------------ */

static int check_array(PyObject *o, const char *name, int typenum, int ndim, npy_intp size,
                       int writeable) {
    if (!PyArray_Check(o)) {
        PyErr_Format(PyExc_TypeError, "%s must be a numpy array", name);
        return -1;
    }
    PyArrayObject *a = (PyArrayObject *)o;
    if (PyArray_TYPE(a) != typenum || !PyArray_IS_C_CONTIGUOUS(a) ||
        (ndim > 0 && PyArray_NDIM(a) != ndim) || (size >= 0 && PyArray_SIZE(a) != size) ||
        (writeable && !PyArray_ISWRITEABLE(a))) {
        PyErr_Format(PyExc_ValueError, "%s: wrong dtype, shape, layout or not writeable", name);
        return -1;
    }
    return 0;
}

/* Direction d: row step and column step. 0-7: straight moves, then diagonals (8 neighbours);
   8-15: knight moves (16 neighbours). A knight move's segment between the two centres crosses
   four cells, each for a quarter of its length (start, the two side cells KS1/KS2, end): e.g.
   (+1, +2) spends t in [0, 1/4] in the start cell, [1/4, 1/2] in (0, +1), [1/2, 3/4] in (+1, +1)
   and [3/4, 1] in the end cell (it crosses column lines at t = 1/4, 3/4 and the row line at
   t = 1/2). Its cost is therefore length x (mean of the four cells' costs + base): the exact cell
   integral of smooth.segment_costs, and it is allowed only when all four cells are passable
   (a knight move never cuts a lethal corner). */
static const int DR[16] = {-1, 1, 0, 0, -1, -1, 1, 1, -2, -2, 2, 2, -1, -1, 1, 1};
static const int DC[16] = {0, 0, -1, 1, -1, 1, -1, 1, -1, 1, -1, 1, -2, 2, -2, 2};
/* the side cells of knight move 8 + i, as (row, col) steps from the start cell */
static const int KS1R[8] = {-1, -1, 1, 1, 0, 0, 0, 0}, KS1C[8] = {0, 0, 0, 0, -1, 1, -1, 1};
static const int KS2R[8] = {-1, -1, 1, 1, -1, -1, 1, 1}, KS2C[8] = {-1, 1, -1, 1, -1, 1, -1, 1};
/* state byte: direction d = (s & ST_DIR) | ((s & ST_KNIGHT) >> 1) */
#define ST_KNIGHT 0x10u
static inline uint8_t dir_state(int d) {
    return (uint8_t)((d & 7) | ST_HAS | (d >= 8 ? ST_KNIGHT : 0));
}
static inline int state_dir(uint8_t s) { return (int)((s & ST_DIR) | ((s & ST_KNIGHT) >> 1)); }

/* ------------------------------------------------------------------------------------------ */
/* search: Dijkstra / A* from one start to one goal (or to everything when goal < 0)          */
/* ------------------------------------------------------------------------------------------ */

/* Rows and columns are npy_intp, never long: long is 32 bits on Windows (LLP64). */
static inline npy_intp iabs(npy_intp x) { return x < 0 ? -x : x; }

static inline double octile(npy_intp ar, npy_intp ac, double dx, double dy, double diag) {
    /* ar, ac >= 0: rows and columns apart */
    npy_intp m = ar < ac ? ar : ac;
    return (double)m * diag + (double)(ac - m) * dx + (double)(ar - m) * dy;
}

typedef struct {
    const float *cost;
    double *dist;
    uint8_t *state;
    volatile const uint8_t *cancel;
    Workspace *ws;
    npy_intp H, W, goal;
    const int64_t *starts; /* cells at distance 0: one start, or expand_many's sources */
    npy_intp nstarts;
    double dx, dy, diag, base, hscale, width;
    size_t ring;
    const uint8_t *region;
    npy_intp Wr;
    int k;
    const float *elev; /* anisotropic mode: elevation in metres per cell (NULL: off) */
    int model;         /* SLOPE_TOBLER or SLOPE_VEHICLE */
    /* results */
    int status;
    double goal_dist;
    size_t settled, pushed;
    int64_t r0, r1, c0, c1;
} Search;

/* Anisotropic mode (an elevation grid and a slope model): a step of ground length L from u to v
   with dz = elev[v] - elev[u] costs (mean of the cells' costs + base) x hypot(L, dz) x f(dz / L),
   so u -> v and v -> u differ. f is a multiplier relative to flat ground (f(0) = 1), the same
   functions as paths.slope_factor (the Python side that prices paths and documents them):
   SLOPE_TOBLER: Tobler's hiking function, speed(s) = 6 exp(-3.5 |s + 0.05|) km/h, f = speed(0) /
   speed(s) = exp(3.5 (|s + 0.05| - 0.05)); minimum exp(-0.175) at s = -0.05.
   SLOPE_VEHICLE (a design choice, see paths.py): 1 + 10 s uphill, 1 + 5 max(0, -s - 0.15)
   downhill (braking), +inf (the step is never taken) where |s| > 0.5; minimum 1.
   The caller scales the A* heuristic by f's minimum (3D length >= ground length, so the
   heuristic stays consistent) and plans with the radix heap (f is unbounded, so no ring width
   covers every step). A cell with a NaN elevation is never entered (its steps cost NaN). */
#define SLOPE_TOBLER 1
#define SLOPE_VEHICLE 2
static inline double slope_factor(int model, double s) {
    if (model == SLOPE_TOBLER) return exp(3.5 * (fabs(s + 0.05) - 0.05));
    if (fabs(s) > 0.5) return INFINITY;
    if (s > 0) return 1.0 + 10.0 * s;
    return -s > 0.15 ? 1.0 + 5.0 * (-s - 0.15) : 1.0;
}
/* hypot(L, dz) x f(dz / L) for the step u -> v of ground length L */
static inline double aniso_len(const Search *S, npy_intp u, npy_intp v, double L) {
    const double dz = (double)S->elev[v] - (double)S->elev[u];
    return sqrt(L * L + dz * dz) * slope_factor(S->model, dz / L);
}

/* The caller's bbox [r0, r1, c0, c1] (inclusive) in, widened over every cell a search wrote; out
   clipped to the grid, so the caller resets only that. */
static inline void bbox_in(Search *S, const int64_t *bbox) {
    S->r0 = bbox[0];
    S->r1 = bbox[1];
    S->c0 = bbox[2];
    S->c1 = bbox[3];
}
static inline void bbox_out(const Search *S, int64_t *bbox) {
    bbox[0] = S->r0 < 0 ? 0 : S->r0;
    bbox[1] = S->r1 > S->H - 1 ? S->H - 1 : S->r1;
    bbox[2] = S->c0 < 0 ? 0 : S->c0;
    bbox[3] = S->c1 > S->W - 1 ? S->W - 1 : S->c1;
}

/* Row of flat index u (0 <= u < 2^32) without a 64-bit division (the division was ~8 % of a
   whole-grid search): a double product is exact to within one, the two compares correct it. */
static inline npy_intp row_of(npy_intp u, npy_intp W, double inv_w) {
    npy_intp r = (npy_intp)((double)u * inv_w);
    if (r * W > u) r--;
    else if ((r + 1) * W <= u) r++;
    return r;
}

/*
 * The search loop, instantiated four times (use_ring = 1: bucket ring, plain Dijkstra; 0: radix
 * heap with A*; knights = 1: 16 neighbours); forced inlining lets the compiler drop the unused
 * branches in each copy.
 *
 * Why it is fast: the loop is bound by memory latency (the cells of one bucket lie scattered
 * along the whole wavefront, so each popped cell's dist/state/cost lines are cache misses). The
 * ring pops the last entry of a bucket, so the next cells to be popped are known: their lines
 * (own row and the rows above and below) are prefetched PREFETCH_AHEAD pops early. The ring's
 * length is a power of two (a mask, not a division, per push) and rows come from row_of().
 */
#define PREFETCH_AHEAD 8
OVERSEEC_FORCE_INLINE void prefetch_cell(const Search *S, npy_intp v, npy_intp span) {
    const npy_intp W = S->W, N = S->H * S->W;
    const npy_intp lo = v - span * W - span, hi = v + span * W + span;
    if (lo < 0 || hi >= N) return;
    OVERSEEC_PREFETCH(S->state + v); /* read at the pop; neighbours' bytes only on a write */
    for (npy_intp q = -span; q <= span; q++) {
        const npy_intp x = v + q * W;
        OVERSEEC_PREFETCH(S->dist + x - span);
        OVERSEEC_PREFETCH(S->dist + x + span);
        OVERSEEC_PREFETCH(S->cost + x);
    }
}

OVERSEEC_FORCE_INLINE void search_loop(Search *S, const int use_ring, const int knights, const int aniso) {
    const float *cost = S->cost;
    double *dist = S->dist;
    uint8_t *state = S->state;
    Workspace *ws = S->ws;
    const npy_intp H = S->H, W = S->W, goal = S->goal;
    const double inv_w = 1.0 / (double)W;
    const double base = S->base, hscale = S->hscale;
    const double inv_width = S->width > 0 ? 1.0 / S->width : 0.0;
    const double dx = S->dx, dy = S->dy, diag = S->diag;
    const double kl_r = hypot(dx, 2.0 * dy), kl_c = hypot(2.0 * dx, dy); /* knight lengths */
    const double len[16] = {dy, dy, dx, dx, diag, diag, diag, diag,
                            kl_r, kl_r, kl_r, kl_r, kl_c, kl_c, kl_c, kl_c};
    const int ndir = knights ? 16 : 8;
    const npy_intp margin = knights ? 2 : 1; /* interior: every neighbour inside the grid */
    const uint8_t *region = S->region;
    const npy_intp Wr = S->Wr;
    const int rk = S->k;
    npy_intp off[16], s1[8], s2[8];
    for (int d = 0; d < 16; d++) off[d] = (npy_intp)DR[d] * W + DC[d];
    for (int i = 0; i < 8; i++) {
        s1[i] = (npy_intp)KS1R[i] * W + KS1C[i];
        s2[i] = (npy_intp)KS2R[i] * W + KS2C[i];
    }
    const npy_intp gr = goal >= 0 ? goal / W : 0, gc = goal >= 0 ? goal % W : 0;
    const int use_h = !use_ring && goal >= 0 && hscale > 0;
    size_t nring = 1;
    while (use_ring && nring < S->ring) nring <<= 1; /* a power of two: index by mask */
    const uint64_t mask = (uint64_t)nring - 1;
    uint64_t cur = 0; /* ring: absolute index of the bucket being emptied */
    uint64_t sorted = UINT64_MAX; /* ring: the bucket last sorted */
    npy_intp last_pf = -16;       /* ring: the cell last prefetched */
    size_t count = 0; /* ring: entries queued */
    int64_t r0 = S->r0, r1 = S->r1, c0 = S->c0, c1 = S->c1;
    size_t settled = 0, pushed = 0;
    int status = 1;

/* A settled neighbour can never be improved: in the ring every step costs more than a bucket's
   width, so du + step > dist[v] for any v settled in this bucket or before (the width keeps a
   1e-6 relative margin, far above rounding), and the test nd < dist[v] fails by itself -- the
   ring skips the state read (a cache line per neighbour row). The radix heap with A* clamps
   keys and compares heuristics in floating point, so it keeps the explicit test. */
#define SKIP_DONE (!use_ring)
/* A* heuristic: octile metres for 8 neighbours; straight-line metres for 16 (a knight step is
   shorter than its octile distance, so octile would overestimate). Both consistent. */
#define HEUR(NR, NC)                                                                           \
    (knights ? hypot((double)((NR) - gr) * dy, (double)((NC) - gc) * dx)                        \
             : octile(iabs((NR) - gr), iabs((NC) - gc), dx, dy, diag))
#define PUSH(V, ND, NR, NC)                                                                    \
    do {                                                                                       \
        int fail_;                                                                             \
        if (use_ring) {                                                                        \
            uint64_t ab_ = (uint64_t)((ND) * inv_width);                                       \
            if (ab_ < cur) ab_ = cur;                                                          \
            fail_ = slot_push(&ws->ring[ab_ & mask], (uint32_t)(V));                           \
            count++;                                                                           \
        } else {                                                                               \
            double key_ = (ND);                                                                \
            if (use_h) key_ += hscale * HEUR(NR, NC);                                          \
            fail_ = heap_push(ws, key_, (uint32_t)(V));                                        \
        }                                                                                      \
        if (fail_) {                                                                           \
            status = -1;                                                                       \
            goto out;                                                                          \
        }                                                                                      \
        pushed++;                                                                              \
    } while (0)
/* relax v (direction d) with the step cost SC; the caller checked v is passable */
#define RELAX(V, D, SC, NR, NC)                                                                \
    do {                                                                                       \
        const double nd_ = du + (SC);                                                          \
        if (nd_ < dist[V]) {                                                                   \
            dist[V] = nd_;                                                                     \
            state[V] = dir_state(D);                                                           \
            PUSH(V, nd_, NR, NC);                                                              \
        }                                                                                      \
    } while (0)

    if (use_ring) {
        if (ring_prepare(ws, nring)) {
            status = -1;
            goto out;
        }
    } else {
        heap_clear(ws);
    }
    for (npy_intp i = 0; i < S->nstarts; i++) {
        const npy_intp s = (npy_intp)S->starts[i];
        const npy_intp sr = s / W, sc = s % W;
        if (sr - margin < r0) r0 = sr - margin;
        if (sr + margin > r1) r1 = sr + margin;
        if (sc - margin < c0) c0 = sc - margin;
        if (sc + margin > c1) c1 = sc + margin;
        dist[s] = 0.0;
        state[s] = 0;
        PUSH(s, 0.0, sr, sc);
    }
    for (;;) {
        npy_intp u;
        if (use_ring) {
            if (count == 0) break;
            Slot *sl = &ws->ring[cur & mask];
            while (sl->n == 0) sl = &ws->ring[++cur & mask];
            if (cur != sorted) { /* a bucket entered: visit its cells in memory order */
                if (sort_desc(ws, sl->v, sl->n)) {
                    status = -1;
                    break;
                }
                sorted = cur;
            }
            u = (npy_intp)sl->v[--sl->n];
            count--;
            if (sl->n >= PREFETCH_AHEAD) {
                /* sorted: the next cells are often neighbours whose lines are on their way */
                const npy_intp e = (npy_intp)sl->v[sl->n - PREFETCH_AHEAD];
                if (e - last_pf > 3 || last_pf - e > 3) prefetch_cell(S, e, margin);
                last_pf = e;
            }
        } else {
            if (ws->size == 0) break;
            uint32_t ui;
            if (heap_pop(ws, &ui)) {
                status = -1;
                break;
            }
            u = (npy_intp)ui;
        }
        if (state[u] & ST_DONE) continue;
        state[u] |= ST_DONE;
        if (u == goal) {
            status = 0;
            S->goal_dist = dist[u];
            break;
        }
        if ((++settled & CANCEL_EVERY) == 0 && S->cancel[0]) {
            status = 2;
            break;
        }
        const npy_intp r = row_of(u, W, inv_w), c = u - r * W;
        if (r - margin < r0) r0 = r - margin;
        if (r + margin > r1) r1 = r + margin;
        if (c - margin < c0) c0 = c - margin;
        if (c + margin > c1) c1 = c + margin;
        const double du = dist[u];
        const double cu = (double)cost[u];
        const double hcu = 0.5 * cu + base;
        if (!region && r >= margin && r < H - margin && c >= margin && c < W - margin) {
            /* interior cell, no corridor: no bounds checks (the common case) */
            for (int d = 0; d < 8; d++) {
                const npy_intp v = u + off[d];
                const float cvf = cost[v];
                if (!(cvf <= FLT_MAX) || (SKIP_DONE && (state[v] & ST_DONE))) continue; /* inf/NaN: blocked */
                const double sl_ = aniso ? aniso_len(S, u, v, len[d]) : len[d];
                RELAX(v, d, (hcu + 0.5 * (double)cvf) * sl_, r + DR[d], c + DC[d]);
            }
            if (knights) {
                for (int i = 0; i < 8; i++) {
                    const int d = 8 + i;
                    const npy_intp v = u + off[d];
                    const float cvf = cost[v], a = cost[u + s1[i]], b = cost[u + s2[i]];
                    if (!(cvf <= FLT_MAX) || !(a <= FLT_MAX) || !(b <= FLT_MAX) ||
                        (SKIP_DONE && (state[v] & ST_DONE)))
                        continue;
                    const double sl_ = aniso ? aniso_len(S, u, v, len[d]) : len[d];
                    const double sc = (0.25 * (cu + (double)a + (double)b + (double)cvf) + base) * sl_;
                    RELAX(v, d, sc, r + DR[d], c + DC[d]);
                }
            }
            continue;
        }
        for (int d = 0; d < ndir; d++) {
            const npy_intp nr = r + DR[d], nc = c + DC[d];
            if ((npy_uintp)nr >= (npy_uintp)H || (npy_uintp)nc >= (npy_uintp)W)
                continue;
            const npy_intp v = u + off[d];
            const float cvf = cost[v];
            if (!(cvf <= FLT_MAX) || (SKIP_DONE && (state[v] & ST_DONE))) continue;
            if (region && !region[(nr / rk) * Wr + nc / rk]) continue;
            double sc;
            const double sl_ = aniso ? aniso_len(S, u, v, len[d]) : len[d];
            if (d < 8) {
                sc = (hcu + 0.5 * (double)cvf) * sl_;
            } else { /* the side cells lie between u and v: inside the grid */
                const float a = cost[u + s1[d - 8]], b = cost[u + s2[d - 8]];
                if (!(a <= FLT_MAX) || !(b <= FLT_MAX)) continue;
                sc = (0.25 * (cu + (double)a + (double)b + (double)cvf) + base) * sl_;
            }
            RELAX(v, d, sc, nr, nc);
        }
    }
#undef RELAX
#undef PUSH
#undef HEUR
#undef SKIP_DONE
out:
    if (status == 1 && goal < 0) status = 0;
    S->status = status;
    S->settled = settled;
    S->pushed = pushed;
    S->r0 = r0;
    S->r1 = r1;
    S->c0 = c0;
    S->c1 = c1;
}

static void search_ring(Search *S) { search_loop(S, 1, 0, 0); }
static void search_heap(Search *S) { search_loop(S, 0, 0, 0); }
static void search_ring16(Search *S) { search_loop(S, 1, 1, 0); }
static void search_heap16(Search *S) { search_loop(S, 0, 1, 0); }
static void search_heap_an(Search *S) { search_loop(S, 0, 0, 1); }
static void search_heap16_an(Search *S) { search_loop(S, 0, 1, 1); }

/*
 * search(*, cost, dist, state, workspace, dx, dy, base, start, cancel, bbox,
 *        hscale=0.0, width=0.0, ring=0, goal=-1, region=None, region_k=1, neighbours=8)
 *     -> (status, goal_dist, settled, pushed)
 *
 * Every argument is keyword-only (call sites name each one; planner.py's Planner._search is the
 * caller). cost (H, W) float32; dist (H*W) float64 and state (H*W) uint8 freshly reset in the
 * area the search may touch. width > 0 and ring >= 2: bucket ring of `ring` (<= MAX_RING)
 * buckets of `width` (every step must cost >= width and <= (ring - 1) * width; hscale is
 * ignored); else radix heap with A* heuristic hscale * octile metres to the goal (0 = Dijkstra;
 * straight-line metres with 16 neighbours). neighbours: 8, or 16 (plus knight moves, priced by
 * the cell integral; the ring must then cover a knight step's cost).
 * elevation: None or (H*W) float32 metres, with slope_model 1 (Tobler) or 2 (vehicle): the
 * anisotropic step rule above slope_factor(); always the radix heap (width/ring are ignored),
 * hscale must already include f's minimum.
 * goal < 0: settle every reachable cell. region: None or (Hr, Wr) uint8, nonzero where the
 * region_k x region_k block may be used (the start's block must be set).
 * cancel: (1,) uint8, polled. bbox: (4,) int64 [r0, r1, c0, c1], widened to cover every cell
 * whose dist/state was written (inclusive), so the caller resets only that.
 * status: 0 = goal settled (or all reachable cells when goal < 0), 1 = goal unreachable,
 * 2 = cancelled.
 */
static PyObject *py_search(PyObject *self, PyObject *args, PyObject *kwargs) {
    (void)self;
    static char *kwlist[] = {"cost",   "dist",   "state", "workspace", "dx",    "dy",
                             "base",   "start",  "cancel", "bbox",     "hscale", "width",
                             "ring",   "goal",   "region", "region_k", "neighbours",
                             "elevation", "slope_model", NULL};
    PyObject *cost_o = NULL, *dist_o = NULL, *state_o = NULL, *cap = NULL, *cancel_o = NULL,
             *bbox_o = NULL, *region_o = Py_None, *elev_o = Py_None;
    double dx = NAN, dy = NAN, base = NAN, hscale = 0.0, width = 0.0;
    Py_ssize_t start = -1, goal = -1, ring = 0;
    int region_k = 1, have_start = 0, neighbours = 8, slope_model = 0;
    /* all keyword-only ("|$"); the required ones are checked below */
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "|$OOOOdddnOOddnnOiiOi", kwlist, &cost_o,
                                     &dist_o, &state_o, &cap, &dx, &dy, &base, &start, &cancel_o,
                                     &bbox_o, &hscale, &width, &ring, &goal, &region_o, &region_k,
                                     &neighbours, &elev_o, &slope_model))
        return NULL;
    if (neighbours != 8 && neighbours != 16) {
        PyErr_SetString(PyExc_ValueError, "neighbours must be 8 or 16");
        return NULL;
    }
    have_start = kwargs && PyDict_GetItemString(kwargs, "start") != NULL;
    if (!cost_o || !dist_o || !state_o || !cap || !cancel_o || !bbox_o || isnan(dx) ||
        isnan(dy) || isnan(base) || !have_start) {
        PyErr_SetString(PyExc_TypeError, "search() needs the keyword arguments cost, dist, state, "
                                         "workspace, dx, dy, base, start, cancel and bbox");
        return NULL;
    }
    if (!PyArray_Check(cost_o) || PyArray_NDIM((PyArrayObject *)cost_o) != 2) {
        PyErr_SetString(PyExc_ValueError, "cost must be a 2-D float32 array");
        return NULL;
    }
    Search S;
    memset(&S, 0, sizeof S);
    S.H = PyArray_DIM((PyArrayObject *)cost_o, 0);
    S.W = PyArray_DIM((PyArrayObject *)cost_o, 1);
    const npy_intp N = S.H * S.W;
    if (check_array(cost_o, "cost", NPY_FLOAT32, 2, N, 0) ||
        check_array(dist_o, "dist", NPY_FLOAT64, -1, N, 1) ||
        check_array(state_o, "state", NPY_UINT8, -1, N, 1) ||
        check_array(cancel_o, "cancel", NPY_UINT8, 1, -1, 0) ||
        check_array(bbox_o, "bbox", NPY_INT64, 1, 4, 1))
        return NULL;
    if (N >= (npy_intp)UINT32_MAX) {
        PyErr_SetString(PyExc_ValueError, "costmap too large for the planner (2^32 cells)");
        return NULL;
    }
    if (start < 0 || start >= N || goal >= N) {
        PyErr_SetString(PyExc_IndexError, "start or goal index outside the grid");
        return NULL;
    }
    if (region_o != Py_None) {
        if (check_array(region_o, "region", NPY_UINT8, 2, -1, 0)) return NULL;
        const npy_intp Hr = PyArray_DIM((PyArrayObject *)region_o, 0);
        S.Wr = PyArray_DIM((PyArrayObject *)region_o, 1);
        if (region_k < 1 || Hr * region_k < S.H || S.Wr * region_k < S.W) {
            PyErr_SetString(PyExc_ValueError, "region does not cover the grid");
            return NULL;
        }
        S.region = (const uint8_t *)PyArray_DATA((PyArrayObject *)region_o);
        S.k = region_k;
    }
    S.ws = (Workspace *)PyCapsule_GetPointer(cap, CAPSULE_NAME);
    if (!S.ws) return NULL;
    if (!(dx > 0 && dy > 0 && base >= 0 && hscale >= 0 && width >= 0 && isfinite(dx) &&
          isfinite(dy) && isfinite(base) && isfinite(hscale) && isfinite(width))) {
        PyErr_SetString(PyExc_ValueError, "pixel sizes must be > 0, base, hscale, width >= 0");
        return NULL;
    }
    if (elev_o != Py_None) {
        if (check_array(elev_o, "elevation", NPY_FLOAT32, -1, N, 0)) return NULL;
        if (slope_model != SLOPE_TOBLER && slope_model != SLOPE_VEHICLE) {
            PyErr_SetString(PyExc_ValueError, "slope_model must be 1 (Tobler) or 2 (vehicle)");
            return NULL;
        }
        S.elev = (const float *)PyArray_DATA((PyArrayObject *)elev_o);
        S.model = slope_model;
    }
    const int use_ring = width > 0 && ring >= 2 && !S.elev;
    if (use_ring && ring > MAX_RING) {
        PyErr_SetString(PyExc_ValueError, "too many ring buckets");
        return NULL;
    }
    S.cost = (const float *)PyArray_DATA((PyArrayObject *)cost_o);
    S.dist = (double *)PyArray_DATA((PyArrayObject *)dist_o);
    S.state = (uint8_t *)PyArray_DATA((PyArrayObject *)state_o);
    S.cancel = (const uint8_t *)PyArray_DATA((PyArrayObject *)cancel_o);
    int64_t *bbox = (int64_t *)PyArray_DATA((PyArrayObject *)bbox_o);
    bbox_in(&S, bbox);
    const int64_t start_cell = (int64_t)start;
    S.starts = &start_cell;
    S.nstarts = 1;
    S.goal = goal;
    S.dx = dx;
    S.dy = dy;
    S.diag = hypot(dx, dy);
    S.base = base;
    S.hscale = hscale;
    S.width = width;
    S.ring = (size_t)ring;
    S.goal_dist = INFINITY;

    Py_BEGIN_ALLOW_THREADS
    if (S.elev)
        neighbours == 16 ? search_heap16_an(&S) : search_heap_an(&S);
    else if (neighbours == 16)
        use_ring ? search_ring16(&S) : search_heap16(&S);
    else
        use_ring ? search_ring(&S) : search_heap(&S);
    Py_END_ALLOW_THREADS

    bbox_out(&S, bbox);
    if (S.status == -1) return PyErr_NoMemory();
    return Py_BuildValue("(idnn)", S.status, S.goal_dist, (Py_ssize_t)S.settled,
                         (Py_ssize_t)S.pushed);
}

/* ------------------------------------------------------------------------------------------ */
/* trace: follow the state bytes back from a settled cell to the start                        */
/* ------------------------------------------------------------------------------------------ */

static PyObject *py_trace(PyObject *self, PyObject *args) {
    (void)self;
    PyObject *state_o;
    Py_ssize_t H, W, end;
    if (!PyArg_ParseTuple(args, "Onnn", &state_o, &H, &W, &end)) return NULL;
    if (H <= 0 || W <= 0 || check_array(state_o, "state", NPY_UINT8, -1, H * W, 0)) return NULL;
    if (end < 0 || end >= H * W) {
        PyErr_SetString(PyExc_IndexError, "end index outside the grid");
        return NULL;
    }
    const uint8_t *state = (const uint8_t *)PyArray_DATA((PyArrayObject *)state_o);
    npy_intp off[16];
    for (int d = 0; d < 16; d++) off[d] = (npy_intp)DR[d] * W + DC[d];
    /* count first, then fill: no growth, no guess */
    npy_intp n = 1, u = end;
    while (state[u] & ST_HAS) {
        u -= off[state_dir(state[u])];
        if (u < 0 || u >= H * W || ++n > H * W) {
            PyErr_SetString(PyExc_RuntimeError, "corrupt planner state while tracing the path");
            return NULL;
        }
    }
    npy_intp dims[2] = {n, 2};
    PyArrayObject *out = (PyArrayObject *)PyArray_SimpleNew(2, dims, NPY_INT64);
    if (!out) return NULL;
    int64_t *p = (int64_t *)PyArray_DATA(out);
    u = end;
    for (npy_intp i = n - 1; i >= 0; i--) {
        p[2 * i] = (int64_t)(u / W);
        p[2 * i + 1] = (int64_t)(u % W);
        if (i > 0) u -= off[state_dir(state[u])];
    }
    return (PyObject *)out;
}

/* ------------------------------------------------------------------------------------------ */
/* reset: write "unvisited" into the cells a search touched                                   */
/* ------------------------------------------------------------------------------------------ */

/* reset(dist, state, H, W, bbox, region, region_k): region None = whole bbox, else only the
   k x k blocks flagged in region (a corridor), clipped to bbox. */
static PyObject *py_reset(PyObject *self, PyObject *args) {
    (void)self;
    PyObject *dist_o, *state_o, *bbox_o, *region_o;
    Py_ssize_t H, W;
    int k;
    if (!PyArg_ParseTuple(args, "OOnnOOi", &dist_o, &state_o, &H, &W, &bbox_o, &region_o, &k))
        return NULL;
    if (H <= 0 || W <= 0 || check_array(dist_o, "dist", NPY_FLOAT64, -1, H * W, 1) ||
        check_array(state_o, "state", NPY_UINT8, -1, H * W, 1) ||
        check_array(bbox_o, "bbox", NPY_INT64, 1, 4, 0))
        return NULL;
    const int64_t *bb = (const int64_t *)PyArray_DATA((PyArrayObject *)bbox_o);
    int64_t r0 = bb[0] < 0 ? 0 : bb[0], r1 = bb[1] > H - 1 ? H - 1 : bb[1];
    int64_t c0 = bb[2] < 0 ? 0 : bb[2], c1 = bb[3] > W - 1 ? W - 1 : bb[3];
    const uint8_t *region = NULL;
    npy_intp Wr = 0;
    if (region_o != Py_None) {
        if (check_array(region_o, "region", NPY_UINT8, 2, -1, 0)) return NULL;
        Wr = PyArray_DIM((PyArrayObject *)region_o, 1);
        if (k < 1 || PyArray_DIM((PyArrayObject *)region_o, 0) * k < H || Wr * k < W) {
            PyErr_SetString(PyExc_ValueError, "region does not cover the grid");
            return NULL;
        }
        region = (const uint8_t *)PyArray_DATA((PyArrayObject *)region_o);
    }
    double *dist = (double *)PyArray_DATA((PyArrayObject *)dist_o);
    uint8_t *state = (uint8_t *)PyArray_DATA((PyArrayObject *)state_o);
    if (r0 > r1 || c0 > c1) Py_RETURN_NONE;
    Py_BEGIN_ALLOW_THREADS
    for (int64_t r = r0; r <= r1; r++) {
        npy_intp row = (npy_intp)r * W;
        if (!region) {
            memset(dist + row + c0, 0x7F, (size_t)(c1 - c0 + 1) * sizeof(double));
            memset(state + row + c0, 0, (size_t)(c1 - c0 + 1));
            continue;
        }
        const uint8_t *rrow = region + (r / k) * Wr;
        int64_t c = c0;
        while (c <= c1) {
            int64_t bend = (c / k + 1) * k - 1;
            if (bend > c1) bend = c1;
            if (rrow[c / k]) {
                memset(dist + row + c, 0x7F, (size_t)(bend - c + 1) * sizeof(double));
                memset(state + row + c, 0, (size_t)(bend - c + 1));
            }
            c = bend + 1;
        }
    }
    Py_END_ALLOW_THREADS
    Py_RETURN_NONE;
}

/* ------------------------------------------------------------------------------------------ */
/* hop_bound: a guaranteed lower bound on the optimal cost from coarse blocks                  */
/* ------------------------------------------------------------------------------------------ */

/*
 * hop_bound(mu, valid, dist, state, workspace, offsets, lengths, start, target_bbox)
 *
 * Dijkstra on the block grid (Hc, Wc) where a block may hop to any block at Chebyshev distance
 * exactly R (offsets: (K, 2) int64) paying mu[from] * lengths[k]; only blocks with valid != 0
 * may be hop targets. Stops at the first settled block inside target_bbox [r0, r1, c0, c1]
 * (inclusive) and returns its distance (inf when none is reachable). dist/state are (Hc*Wc)
 * scratch buffers, reset here. Why this is a lower bound: hop_offsets() in planner.py.
 */
static PyObject *py_hop_bound(PyObject *self, PyObject *args) {
    (void)self;
    PyObject *mu_o, *valid_o, *dist_o, *state_o, *cap, *offs_o, *lens_o, *tb_o;
    Py_ssize_t start;
    if (!PyArg_ParseTuple(args, "OOOOOOOnO", &mu_o, &valid_o, &dist_o, &state_o, &cap, &offs_o,
                          &lens_o, &start, &tb_o))
        return NULL;
    if (!PyArray_Check(mu_o) || PyArray_NDIM((PyArrayObject *)mu_o) != 2) {
        PyErr_SetString(PyExc_ValueError, "mu must be a 2-D float64 array");
        return NULL;
    }
    const npy_intp H = PyArray_DIM((PyArrayObject *)mu_o, 0);
    const npy_intp W = PyArray_DIM((PyArrayObject *)mu_o, 1);
    const npy_intp N = H * W;
    if (check_array(mu_o, "mu", NPY_FLOAT64, 2, N, 0) ||
        check_array(valid_o, "valid", NPY_UINT8, -1, N, 0) ||
        check_array(dist_o, "dist", NPY_FLOAT64, -1, N, 1) ||
        check_array(state_o, "state", NPY_UINT8, -1, N, 1) ||
        check_array(offs_o, "offsets", NPY_INT64, 2, -1, 0) ||
        check_array(lens_o, "lengths", NPY_FLOAT64, 1, -1, 0) ||
        check_array(tb_o, "target", NPY_INT64, 1, 4, 0))
        return NULL;
    const npy_intp K = PyArray_DIM((PyArrayObject *)offs_o, 0);
    if (PyArray_DIM((PyArrayObject *)offs_o, 1) != 2 ||
        PyArray_DIM((PyArrayObject *)lens_o, 0) != K || start < 0 || start >= N ||
        N >= (npy_intp)UINT32_MAX) {
        PyErr_SetString(PyExc_ValueError, "bad offsets, lengths or start");
        return NULL;
    }
    Workspace *heap = (Workspace *)PyCapsule_GetPointer(cap, CAPSULE_NAME);
    if (!heap) return NULL;
    const double *mu = (const double *)PyArray_DATA((PyArrayObject *)mu_o);
    const uint8_t *valid = (const uint8_t *)PyArray_DATA((PyArrayObject *)valid_o);
    double *dist = (double *)PyArray_DATA((PyArrayObject *)dist_o);
    uint8_t *state = (uint8_t *)PyArray_DATA((PyArrayObject *)state_o);
    const int64_t *offs = (const int64_t *)PyArray_DATA((PyArrayObject *)offs_o);
    const double *lens = (const double *)PyArray_DATA((PyArrayObject *)lens_o);
    const int64_t *tb = (const int64_t *)PyArray_DATA((PyArrayObject *)tb_o);
    double result = INFINITY;
    int oom = 0;

    Py_BEGIN_ALLOW_THREADS
    for (npy_intp i = 0; i < N; i++) dist[i] = INFINITY;
    memset(state, 0, (size_t)N);
    heap_clear(heap);
    dist[start] = 0.0;
    if (heap_push(heap, 0.0, (uint32_t)start)) oom = 1;
    while (!oom && heap->size > 0) {
        uint32_t ui;
        if (heap_pop(heap, &ui)) {
            oom = 1;
            break;
        }
        const npy_intp u = (npy_intp)ui;
        if (state[u]) continue;
        state[u] = 1;
        const int64_t r = u / W, c = u % W;
        if (r >= tb[0] && r <= tb[1] && c >= tb[2] && c <= tb[3]) {
            result = dist[u];
            break;
        }
        const double du = dist[u], m = mu[u];
        if (!(m < INFINITY)) continue;
        for (npy_intp k = 0; k < K; k++) {
            const int64_t nr = r + offs[2 * k], nc = c + offs[2 * k + 1];
            if (nr < 0 || nr >= H || nc < 0 || nc >= W) continue;
            const npy_intp v = (npy_intp)(nr * W + nc);
            if (!valid[v] || state[v]) continue;
            const double nd = du + m * lens[k];
            if (nd < dist[v]) {
                dist[v] = nd;
                if (heap_push(heap, nd, (uint32_t)v)) {
                    oom = 1;
                    break;
                }
            }
        }
    }
    Py_END_ALLOW_THREADS
    if (oom) return PyErr_NoMemory();
    return PyFloat_FromDouble(result);
}

/* ------------------------------------------------------------------------------------------ */
/* expand_many: the cost-distance field from a set of source cells                            */
/* ------------------------------------------------------------------------------------------ */

/*
 * expand_many(cost, dist, state, workspace, dx, dy, base, sources, cancel, bbox)
 *     -> (status, settled)
 *
 * Dijkstra (8 neighbours) from every cell of sources ((K,) int64 flat indices, each at distance 0) to every
 * reachable cell: search()'s own loop (search_heap: radix heap, no heuristic, goal -1) seeded with
 * every source, so the step rule is the same code (mean of the two cells' costs + base, times the
 * step length; +inf/NaN cells never entered). dist[v] is then the cost of the cheapest route from
 * the nearest source, and the state bytes lead trace() back to that source.
 * dist/state must be reset in the area touched (as for search()); bbox is widened to it.
 * Sources on a blocked cell are the caller's error (checked in Python); duplicates are fine.
 * status: 0 = done, 2 = cancelled (polled every 16384 cells).
 */
static PyObject *py_expand_many(PyObject *self, PyObject *args) {
    (void)self;
    PyObject *cost_o, *dist_o, *state_o, *cap, *src_o, *cancel_o, *bbox_o;
    double dx, dy, base;
    if (!PyArg_ParseTuple(args, "OOOOdddOOO", &cost_o, &dist_o, &state_o, &cap, &dx, &dy, &base, &src_o,
                          &cancel_o, &bbox_o))
        return NULL;
    if (!PyArray_Check(cost_o) || PyArray_NDIM((PyArrayObject *)cost_o) != 2) {
        PyErr_SetString(PyExc_ValueError, "cost must be a 2-D float32 array");
        return NULL;
    }
    const npy_intp H = PyArray_DIM((PyArrayObject *)cost_o, 0);
    const npy_intp W = PyArray_DIM((PyArrayObject *)cost_o, 1);
    const npy_intp N = H * W;
    if (check_array(cost_o, "cost", NPY_FLOAT32, 2, N, 0) ||
        check_array(dist_o, "dist", NPY_FLOAT64, -1, N, 1) ||
        check_array(state_o, "state", NPY_UINT8, -1, N, 1) ||
        check_array(src_o, "sources", NPY_INT64, 1, -1, 0) ||
        check_array(cancel_o, "cancel", NPY_UINT8, 1, -1, 0) ||
        check_array(bbox_o, "bbox", NPY_INT64, 1, 4, 1))
        return NULL;
    if (N >= (npy_intp)UINT32_MAX) {
        PyErr_SetString(PyExc_ValueError, "costmap too large for the planner (2^32 cells)");
        return NULL;
    }
    if (!(dx > 0 && dy > 0 && base >= 0 && isfinite(dx) && isfinite(dy) && isfinite(base))) {
        PyErr_SetString(PyExc_ValueError, "pixel sizes must be > 0 and base >= 0");
        return NULL;
    }
    const npy_intp K = PyArray_SIZE((PyArrayObject *)src_o);
    const int64_t *src = (const int64_t *)PyArray_DATA((PyArrayObject *)src_o);
    for (npy_intp i = 0; i < K; i++) {
        if (src[i] < 0 || src[i] >= N) {
            PyErr_SetString(PyExc_IndexError, "source index outside the grid");
            return NULL;
        }
    }
    Search S;
    memset(&S, 0, sizeof S);
    S.ws = (Workspace *)PyCapsule_GetPointer(cap, CAPSULE_NAME);
    if (!S.ws) return NULL;
    S.cost = (const float *)PyArray_DATA((PyArrayObject *)cost_o);
    S.dist = (double *)PyArray_DATA((PyArrayObject *)dist_o);
    S.state = (uint8_t *)PyArray_DATA((PyArrayObject *)state_o);
    S.cancel = (const uint8_t *)PyArray_DATA((PyArrayObject *)cancel_o);
    int64_t *bbox = (int64_t *)PyArray_DATA((PyArrayObject *)bbox_o);
    S.H = H;
    S.W = W;
    bbox_in(&S, bbox);
    S.starts = src;
    S.nstarts = K;
    S.goal = -1;
    S.dx = dx;
    S.dy = dy;
    S.diag = hypot(dx, dy);
    S.base = base;
    S.goal_dist = INFINITY;

    Py_BEGIN_ALLOW_THREADS
    search_heap(&S);
    Py_END_ALLOW_THREADS

    bbox_out(&S, bbox);
    if (S.status == -1) return PyErr_NoMemory();
    return Py_BuildValue("(in)", S.status, (Py_ssize_t)S.settled);
}

static PyMethodDef methods[] = {
    {"workspace", py_workspace, METH_NOARGS, "A reusable priority-queue workspace (capsule)."},
    {"workspace_bytes", py_workspace_bytes, METH_VARARGS, "Bytes a workspace holds."},
    {"search", (PyCFunction)(void (*)(void))py_search, METH_VARARGS | METH_KEYWORDS,
     "Dijkstra/A* on an 8-connected costmap grid (keyword arguments only)."},
    {"trace", py_trace, METH_VARARGS, "Path (N, 2) int64 rows/cols from the state bytes."},
    {"reset", py_reset, METH_VARARGS, "Mark touched cells unvisited again."},
    {"hop_bound", py_hop_bound, METH_VARARGS, "Lower bound on a path cost from coarse blocks."},
    {"expand_many", py_expand_many, METH_VARARGS, "Cost-distance field from a set of source cells."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef moduledef = {
    PyModuleDef_HEAD_INIT, "_kernel", "overseec planner kernel (see _kernel.c).", -1, methods,
    NULL, NULL, NULL, NULL, /* m_slots, m_traverse, m_clear, m_free */
};

PyMODINIT_FUNC PyInit__kernel(void) {
    import_array();
    PyObject *m = PyModule_Create(&moduledef);
    if (!m) return NULL;
    if (PyModule_AddIntConstant(m, "MAX_RING", MAX_RING)) {
        Py_DECREF(m);
        return NULL;
    }
    /* The slope model ids this kernel knows, by name: the planner checks them against its own
       table (overseec_core.defaults.SLOPE_MODEL_IDS) when it loads the kernel. */
    PyObject *ids = Py_BuildValue("{s:i,s:i}", "tobler", SLOPE_TOBLER, "vehicle", SLOPE_VEHICLE);
    if (!ids || PyModule_AddObject(m, "SLOPE_MODEL_IDS", ids)) {
        Py_XDECREF(ids);
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
