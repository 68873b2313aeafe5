"""Distances, crossings and ray hits on polygons of many edges, in O(n log n).

An outline read from a CAD export may have thousands of edges; comparing every edge
with every other (or every ray with every edge) then costs gigabytes. Here the
candidates come from a k-d tree over the edges' midpoints: two edges can only touch
when their midpoints are within half their lengths' sum, a ray can only hit an edge
within distance t when the edge's midpoint is within t + half its length. The few long
edges (much longer than the median, which would make those radii large) are compared
with everything directly. Below :data:`BRUTE_FORCE_PAIRS` pairs everything is compared
directly, so small polygons take exactly the direct path.
"""

from __future__ import annotations

import itertools

import numpy as np

__all__ = ["BRUTE_FORCE_PAIRS", "crossing_pairs", "ray_hits", "segment_distances"]

#: Up to this many (item, edge) pairs the direct comparison is used (a few tens of MB).
BRUTE_FORCE_PAIRS = 2_000_000
#: Rays searched together (their candidate edges held at once).
RAY_BATCH = 1024
#: An edge longer than this many median lengths is compared with everything directly.
LONG_EDGE = 8.0


def _split_long(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Indices of the short and the long edges, and the longest short edge's length."""
    length = np.hypot(*(b - a).T)
    cut = LONG_EDGE * float(np.median(length))
    short = np.flatnonzero(length <= cut)
    long_ = np.flatnonzero(length > cut)
    return short, long_, float(length[short].max(initial=0.0))


def _chunks(n_items: int, n_edges: int):
    step = max(1, BRUTE_FORCE_PAIRS // max(n_edges, 1))
    for lo in range(0, n_items, step):
        yield slice(lo, min(n_items, lo + step))


def _group_min(out: np.ndarray, rows: np.ndarray, values: np.ndarray) -> None:
    """out[rows] = min(out[rows], values), the minimum over repeated rows (a sorted
    reduction: numpy's minimum.at is slow)."""
    if not len(rows):
        return
    order = np.argsort(rows, kind="stable")
    r, v = rows[order], values[order]
    first = np.flatnonzero(np.r_[True, r[1:] != r[:-1]])
    out[r[first]] = np.minimum(out[r[first]], np.minimum.reduceat(v, first))


def _point_segment(xy: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of each point to each edge, element-wise over broadcast shapes."""
    d = b - a
    den = np.maximum(np.sum(d * d, axis=-1), 1e-300)
    t = np.clip(np.sum((xy - a) * d, axis=-1) / den, 0.0, 1.0)
    return np.hypot(*np.moveaxis(xy - (a + t[..., None] * d), -1, 0))


def segment_distances(xy: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The distance of each point (N, 2) to the nearest of the straight edges a -> b
    (E, 2), shape (N,)."""
    xy = np.atleast_2d(np.asarray(xy, float))
    best = np.full(len(xy), np.inf)
    if len(a) == 0:
        return best
    if len(xy) * len(a) <= BRUTE_FORCE_PAIRS:
        return _point_segment(xy[:, None, :], a[None], b[None]).min(axis=1)
    from scipy.spatial import cKDTree

    short, long_, reach = _split_long(a, b)
    for sl in _chunks(len(xy), len(long_)):
        if len(long_):
            best[sl] = _point_segment(xy[sl, None, :], a[None, long_], b[None, long_]).min(axis=1)
    # the nearest vertex bounds the distance: the nearest short edge's midpoint is
    # within that bound plus half the longest short edge
    bound, _ = cKDTree(np.concatenate([a, b])).query(xy)
    mid = cKDTree(0.5 * (a[short] + b[short]))
    lists = mid.query_ball_point(xy, bound + 0.5 * reach * (1 + 1e-9), return_sorted=False)
    counts = np.fromiter(map(len, lists), dtype=np.int64, count=len(lists))
    rows = np.repeat(np.arange(len(xy)), counts)
    cols = short[np.fromiter(itertools.chain.from_iterable(lists), dtype=np.int64, count=int(counts.sum()))]
    for sl in _chunks(len(rows), 1):
        _group_min(best, rows[sl], _point_segment(xy[rows[sl]], a[cols[sl]], b[cols[sl]]))
    return best


def _orient(p1, p2, p3):
    return (p2[..., 0] - p1[..., 0]) * (p3[..., 1] - p1[..., 1]) - (p2[..., 1] - p1[..., 1]) * (
        p3[..., 0] - p1[..., 0]
    )


def _touching(a, b, i, j) -> np.ndarray:
    """Whether edges i and j (index arrays) cross or, collinear, overlap."""
    o1, o2 = _orient(a[i], b[i], a[j]), _orient(a[i], b[i], b[j])
    o3, o4 = _orient(a[j], b[j], a[i]), _orient(a[j], b[j], b[i])
    hit = (np.sign(o1) != np.sign(o2)) & (np.sign(o3) != np.sign(o4))
    flat = (o1 == 0) & (o2 == 0) & (o3 == 0) & (o4 == 0)
    if flat.any():
        lo_i, hi_i = np.minimum(a[i], b[i]), np.maximum(a[i], b[i])
        lo_j, hi_j = np.minimum(a[j], b[j]), np.maximum(a[j], b[j])
        hit |= flat & np.all((lo_i <= hi_j) & (lo_j <= hi_i), axis=1)
    return hit


def crossing_pairs(a: np.ndarray, b: np.ndarray) -> tuple[int, int] | None:
    """The first pair (i, j), i < j, of edges of the closed polygon a -> b that cross or
    overlap, neighbours (which share a vertex) excluded; None if the polygon is simple."""
    p = len(a)

    def not_adjacent(i, j):
        return (j != i + 1) & ~((i == 0) & (j == p - 1)) & (i != j)

    if p * p // 2 <= BRUTE_FORCE_PAIRS:
        i, j = np.triu_indices(p, 1)
        candidates = [(i, j)]
    else:
        from scipy.spatial import cKDTree

        short, long_, reach = _split_long(a, b)
        pairs = cKDTree(0.5 * (a[short] + b[short])).query_pairs(reach * (1 + 1e-9), output_type="ndarray")
        candidates = [(short[pairs[:, 0]], short[pairs[:, 1]])] if len(pairs) else []
        for k in long_:  # each long edge against every edge
            others = np.arange(p)
            candidates.append((np.full(p, k), others))
    for i, j in candidates:
        i, j = np.minimum(i, j), np.maximum(i, j)
        keep = not_adjacent(i, j)
        i, j = i[keep], j[keep]
        for sl in _chunks(len(i), 1):
            hit = _touching(a, b, i[sl], j[sl])
            if hit.any():
                m = int(np.argmax(hit))
                return int(i[sl][m]), int(j[sl][m])
    return None


def _ray_edge(start, direction, a, b, facing: float | None = None) -> np.ndarray:
    """Distance along each ray to each edge it crosses (inf where it does not),
    element-wise over broadcast shapes; with ``facing``, only edges the ray meets at
    most that far from head-on (the cosine of the angle between the ray and the edge's
    normal at least ``facing``)."""
    e = b - a
    w = a - start
    den = direction[..., 0] * e[..., 1] - direction[..., 1] * e[..., 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[..., 0] * e[..., 1] - w[..., 1] * e[..., 0]) / den
        u = (w[..., 0] * direction[..., 1] - w[..., 1] * direction[..., 0]) / den
        ok = (np.abs(den) > 1e-300) & (t > 0) & (u >= 0) & (u <= 1)
        if facing is not None:  # |sin| of the angle between ray and edge = |cos| to the normal
            ok &= np.abs(den) >= facing * np.hypot(e[..., 0], e[..., 1])
    return np.where(ok, t, np.inf)


def ray_hits(
    start: np.ndarray, direction: np.ndarray, a: np.ndarray, b: np.ndarray, facing: float | None = None
) -> np.ndarray:
    """Distance from each start point (R, 2) along its unit direction to the first edge
    a -> b it hits (inf if none; with ``facing``, the first it meets within that cosine
    of head-on, see :func:`_ray_edge`), for the rays that can hold the smallest of these
    distances: a ray whose first hit is beyond the smallest one found may be reported
    as inf (the caller wants the minimum)."""
    n = len(start)
    if n * len(a) <= BRUTE_FORCE_PAIRS:
        out = np.empty(n)
        for sl in _chunks(n, len(a)):
            out[sl] = _ray_edge(start[sl, None, :], direction[sl, None, :], a[None], b[None], facing).min(
                axis=1
            )
        return out
    from scipy.spatial import cKDTree

    short, long_, reach = _split_long(a, b)
    out = np.full(n, np.inf)
    for sl in _chunks(n, len(long_)):
        if len(long_):
            hits = _ray_edge(
                start[sl, None, :], direction[sl, None, :], a[None, long_], b[None, long_], facing
            )
            out[sl] = hits.min(axis=1)
    tree = cKDTree(0.5 * (a[short] + b[short]))
    extent = float(np.ptp(np.concatenate([a, b]), axis=0).max())
    # search rings of growing radius: a hit within r is exact; rays without one need a
    # larger r only while r is below the smallest hit found (rays in batches, so that
    # the candidate pairs stay within a few hundred MB)
    for batch in range(0, n, RAY_BATCH):
        pending = np.arange(batch, min(n, batch + RAY_BATCH))
        r = 4.0 * reach
        while len(pending):
            near = cKDTree(start[pending]).sparse_distance_matrix(
                tree, r + 0.5 * reach * (1 + 1e-9), output_type="ndarray"
            )
            rows, cols = pending[near["i"]], short[near["j"]]
            for sl in _chunks(len(rows), 1):
                t = _ray_edge(start[rows[sl]], direction[rows[sl]], a[cols[sl]], b[cols[sl]], facing)
                _group_min(out, rows[sl], np.where(t <= r, t, np.inf))
            # a ray is settled once its hit is within r (every edge that near was
            # tried); one not settled has its hit beyond r, so it matters only while
            # r < the smallest hit found
            pending = pending[out[pending] > r]
            if not len(pending) or r >= float(out.min()) or r > 2.0 * extent:
                break
            r *= 4.0
    return out
