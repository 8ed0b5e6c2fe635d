// The ray core: voxel-by-voxel traversal (3D-DDA) and exact ray-isosurface intersection in each cell
// (paper §5.1). Compiled as GLSL by the passes, as C++ by the host tests, and as CUDA by cuda_ref/.
//
// The includer defines, before including this file:
//   float rcFetch(ivec3 p)   the sample at integer index p (unfiltered), in texture units.
// All positions are in index space: sample (i,j,k) sits at (i,j,k); cell c spans [c, c+1].
#ifndef ISO_RAY_CORE_H
#define ISO_RAY_CORE_H

#include "portable.h"

#ifndef ISO_GLSL
namespace iso::rc {
#endif

#define RC_INFINITY 3.0e38f
#define RC_BISECTIONS 22

struct RcHit {
    float t;    // ray parameter of the hit (world distance); < 0 when nothing was hit
    ivec3 cell; // lowest corner of the cell that holds the hit
    vec3 pos;   // index-space position of the hit
};

// Clips [t0, t1] to the box. Zero direction components are handled explicitly: IEEE division would
// give 0 * inf = NaN for rays that lie exactly in a slab plane, and such rays count as inside.
RC_FN bool rcClipBox(vec3 o, vec3 d, vec3 bmin, vec3 bmax, RC_INOUT(float) t0, RC_INOUT(float) t1) {
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < bmin[a] || o[a] > bmax[a]) return false;
        } else {
            float inv = 1.0f / d[a];
            float ta = (bmin[a] - o[a]) * inv;
            float tb = (bmax[a] - o[a]) * inv;
            t0 = max(t0, min(ta, tb));
            t1 = min(t1, max(ta, tb));
        }
    }
    return t0 <= t1;
}

// Coefficients (c0, c1, c2, c3) of g(s) = f(a + s*d) - iso, where f is the trilinear interpolant of
// the cell's corners c[i + 2j + 4k] and a is the local entry point. Taken from the 8 corner values,
// so the cubic is the interpolant itself, not a fit: interpolate along x (linear in s), then y
// (quadratic), then z (cubic).
RC_FN vec4 rcCellCubic(float c[8], vec3 a, vec3 d, float iso) {
    vec2 e[4];
    for (int jk = 0; jk < 4; ++jk) {
        float c0 = c[2 * jk];
        float dc = c[2 * jk + 1] - c0;
        e[jk] = vec2(c0 + a.x * dc, d.x * dc);
    }
    vec3 q[2];
    for (int k = 0; k < 2; ++k) {
        vec2 e0 = e[2 * k];
        vec2 de = e[2 * k + 1] - e0;
        q[k] = vec3(e0.x + a.y * de.x, e0.y + a.y * de.y + d.y * de.x, d.y * de.y);
    }
    vec3 dq = q[1] - q[0];
    return vec4(q[0].x + a.z * dq.x - iso, q[0].y + a.z * dq.y + d.z * dq.x, q[0].z + a.z * dq.z + d.z * dq.y,
                d.z * dq.z);
}

RC_FN float rcCubicAt(vec4 c, float s) {
    return ((c.w * s + c.z) * s + c.y) * s + c.x;
}

// The first root of g in the monotone piece [lo, hi], given g's values at the ends.
// "f >= iso is inside", so an exact zero is a hit and a sign change is judged by g >= 0.
RC_FN bool rcRootInPiece(vec4 c, float lo, float hi, float glo, float ghi, RC_INOUT(float) s) {
    if (glo == 0.0) {
        s = lo;
        return true;
    }
    if ((glo >= 0.0) == (ghi >= 0.0)) return false;
    // Bisection keeps the bracket (and so the first-root guarantee) in float; a final secant
    // step between the bracket ends removes most of the remaining error.
    bool loInside = glo >= 0.0;
    for (int i = 0; i < RC_BISECTIONS; ++i) {
        float mid = 0.5f * (lo + hi);
        float gm = rcCubicAt(c, mid);
        if ((gm >= 0.0) == loInside) {
            lo = mid;
            glo = gm;
        } else {
            hi = mid;
            ghi = gm;
        }
    }
    float denom = glo - ghi;
    s = denom != 0.0 ? clamp(lo + (hi - lo) * glo / denom, lo, hi) : lo;
    return true;
}

// The first root of the cubic on [0, len] after sAfter, by Marmitt et al.: the roots of g' split
// [0, len] into monotone pieces, which are tested in order, and the first with a sign change is
// refined. Each piece holds at most one root, and a root is found by the same steps however the
// search started, so successive calls with sAfter = the last root count every crossing once
// (the surface peeling of paper §5.2); sAfter < 0 asks for the first root.
RC_FN bool rcNextRoot(vec4 c, float len, float sAfter, RC_INOUT(float) s) {
    float split0 = len;
    float split1 = len;
    float qa = 3.0f * c.w;
    float qb = 2.0f * c.z;
    float qc = c.y;
    if (qa != 0.0) {
        float disc = qb * qb - 4.0f * qa * qc;
        if (disc > 0.0) {
            // Stable quadratic roots (no cancellation between -b and the square root).
            float qq = -0.5f * (qb + (qb >= 0.0 ? sqrt(disc) : -sqrt(disc)));
            float r0 = qq / qa;
            float r1 = qq != 0.0 ? qc / qq : r0;
            split0 = min(r0, r1);
            split1 = max(r0, r1);
        }
    } else if (qb != 0.0) {
        split0 = -qc / qb;
    }
    if (!(split0 > 0.0 && split0 < len)) split0 = len;
    if (!(split1 > 0.0 && split1 < len)) split1 = len;
    if (split1 < split0) {
        float tmp = split0;
        split0 = split1;
        split1 = tmp;
    }
    // Roots closer than this to the previous one are that root seen again (from a neighbouring
    // cell when it lies on a shared face).
    float after = sAfter + 1.0e-5f * len;
    float bounds[4];
    bounds[0] = 0.0;
    bounds[1] = split0;
    bounds[2] = split1;
    bounds[3] = len;
    float glo = c.x;
    for (int k = 0; k < 3; ++k) {
        float ghi = rcCubicAt(c, bounds[k + 1]);
        if (bounds[k + 1] > after && rcRootInPiece(c, bounds[k], bounds[k + 1], glo, ghi, s) && s > after)
            return true;
        glo = ghi;
    }
    if (glo == 0.0 && len > after) {
        s = len;
        return true;
    }
    return false;
}

RC_FN bool rcFirstRoot(vec4 c, float len, RC_INOUT(float) s) {
    return rcNextRoot(c, len, -1.0f, s);
}

RC_FN void rcFetchCorners(ivec3 cell, RC_OUT_ARRAY(float) c[8]) {
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) c[i + 2 * j + 4 * k] = rcFetch(cell + ivec3(i, j, k));
}

// Trilinear interpolation at an index-space point, clamped to the grid.
RC_FN float rcSample(vec3 p, ivec3 dims) {
    vec3 q = clamp(p, vec3(0.0), vec3(dims - ivec3(1)));
    ivec3 cell = min(ivec3(floor(q)), max(dims - ivec3(2), ivec3(0)));
    vec3 w = q - vec3(cell);
    float c[8];
    rcFetchCorners(cell, c);
    float x00 = c[0] + w.x * (c[1] - c[0]);
    float x10 = c[2] + w.x * (c[3] - c[2]);
    float x01 = c[4] + w.x * (c[5] - c[4]);
    float x11 = c[6] + w.x * (c[7] - c[6]);
    float y0 = x00 + w.y * (x10 - x00);
    float y1 = x01 + w.y * (x11 - x01);
    return y0 + w.z * (y1 - y0);
}

// Index-space gradient from the 6 neighbouring samples of the interpolant (paper §4.3).
RC_FN vec3 rcGradient(vec3 p, ivec3 dims) {
    return 0.5f * vec3(rcSample(p + vec3(1, 0, 0), dims) - rcSample(p - vec3(1, 0, 0), dims),
                       rcSample(p + vec3(0, 1, 0), dims) - rcSample(p - vec3(0, 1, 0), dims),
                       rcSample(p + vec3(0, 0, 1), dims) - rcSample(p - vec3(0, 0, 1), dims));
}

// Voxel-by-voxel traversal state (Amanatides-Woo 3D-DDA) over the cells of a box.
struct RcDda {
    ivec3 cell;    // current cell (its lowest corner)
    ivec3 stepDir; // -1, 0 or +1 per axis
    vec3 invD;     // 1 / d, 0 where d is 0
    ivec3 lowCell; // cells the box touches
    ivec3 highCell;
    float tIn;  // where the ray enters the current cell
    float tEnd; // where it leaves the box
};

// Starts the traversal at the ray's entry into the box (or at t = 0 inside it).
RC_FN bool rcDdaBegin(vec3 o, vec3 d, vec3 bmin, vec3 bmax, ivec3 dims, RC_OUT(RcDda) s) {
    float t0 = 0.0;
    float t1 = RC_INFINITY;
    s.tIn = 0.0;
    s.tEnd = -1.0;
    s.cell = ivec3(0);
    s.stepDir = ivec3(0);
    s.invD = vec3(0.0);
    s.lowCell = ivec3(0);
    s.highCell = ivec3(-1);
    if (!rcClipBox(o, d, bmin, bmax, t0, t1)) return false;
    ivec3 cellMax = max(dims - ivec3(2), ivec3(0));
    s.lowCell = clamp(ivec3(floor(bmin)), ivec3(0), cellMax);
    s.highCell = clamp(ivec3(ceil(bmax)) - ivec3(1), ivec3(0), cellMax);
    s.cell = clamp(ivec3(floor(o + t0 * d)), s.lowCell, s.highCell);
    s.stepDir = ivec3(d.x > 0.0 ? 1 : (d.x < 0.0 ? -1 : 0), d.y > 0.0 ? 1 : (d.y < 0.0 ? -1 : 0),
                      d.z > 0.0 ? 1 : (d.z < 0.0 ? -1 : 0));
    s.invD =
        vec3(d.x != 0.0 ? 1.0f / d.x : 0.0, d.y != 0.0 ? 1.0f / d.y : 0.0, d.z != 0.0 ? 1.0f / d.z : 0.0);
    s.tIn = t0;
    s.tEnd = t1;
    return true;
}

// Where the ray leaves the current cell along each axis. Computed from the cell index each time
// rather than accumulated, so no error builds up over long traversals.
RC_FN vec3 rcDdaAxisExits(vec3 o, RcDda s) {
    vec3 tExit;
    for (int a = 0; a < 3; ++a) {
        if (s.stepDir[a] == 0) {
            tExit[a] = RC_INFINITY;
        } else {
            float plane = float(s.cell[a] + (s.stepDir[a] > 0 ? 1 : 0));
            tExit[a] = (plane - o[a]) * s.invD[a];
        }
    }
    return tExit;
}

RC_FN float rcDdaCellExit(vec3 tExit, RcDda s) {
    return min(min(min(tExit.x, tExit.y), tExit.z), s.tEnd);
}

// Moves to the next cell; false when the ray has left the box. All axes whose boundaries the ray
// reaches at tOut are stepped together, so rays through edges and corners visit exactly the cells
// they cross, never a cell they only touch.
RC_FN bool rcDdaStep(RC_INOUT(RcDda) s, vec3 tExit, float tOut) {
    if (tOut >= s.tEnd) return false;
    for (int a = 0; a < 3; ++a)
        if (tExit[a] <= tOut) s.cell[a] += s.stepDir[a];
    s.tIn = tOut;
    return !(any(lessThan(s.cell, s.lowCell)) || any(greaterThan(s.cell, s.highCell)));
}

// The hit of the ray o + t*d (t >= 0) with {f = iso} inside the box [bmin, bmax] after `skip`
// earlier crossings (0: the first hit; peeling windows raise it).
RC_FN RcHit rcTraceIso(vec3 o, vec3 d, vec3 bmin, vec3 bmax, ivec3 dims, float iso, int skip) {
    RcHit hit;
    hit.t = -1.0;
    hit.cell = ivec3(0);
    hit.pos = vec3(0.0);
    RcDda s;
    if (!rcDdaBegin(o, d, bmin, bmax, dims, s)) return hit;
    float tLast = -RC_INFINITY; // the last crossing passed over
    int maxSteps = dims.x + dims.y + dims.z + 3;
    for (int n = 0; n < maxSteps; ++n) {
        vec3 tExit = rcDdaAxisExits(o, s);
        float tOut = rcDdaCellExit(tExit, s);
        float c[8];
        rcFetchCorners(s.cell, c);
        float lo = min(min(min(c[0], c[1]), min(c[2], c[3])), min(min(c[4], c[5]), min(c[6], c[7])));
        float hi = max(max(max(c[0], c[1]), max(c[2], c[3])), max(max(c[4], c[5]), max(c[6], c[7])));
        // The interpolant stays within its corners' range, so most cells are rejected here.
        bool candidate = lo <= iso && iso <= hi && tOut >= s.tIn;
#if ISO_VOLUME_KIND == 0
        // Float scans may hold NaN or Inf: such a cell holds no surface (min/max may drop a NaN,
        // so every corner is checked), and its neighbours never see the non-finite value.
        for (int i = 0; i < 8; ++i) candidate = candidate && !isnan(c[i]) && !isinf(c[i]);
#endif
        if (candidate) {
            vec3 a = o + s.tIn * d - vec3(s.cell);
            vec4 cubic = rcCellCubic(c, a, d, iso);
            float len = tOut - s.tIn;
            float root;
            float sAfter = max(tLast - s.tIn, -1.0f);
            while (rcNextRoot(cubic, len, sAfter, root)) {
                if (skip == 0) {
                    hit.t = s.tIn + root;
                    hit.cell = s.cell;
                    hit.pos = o + hit.t * d;
                    return hit;
                }
                --skip;
                tLast = s.tIn + root;
                sAfter = root;
            }
        }
        if (!rcDdaStep(s, tExit, tOut)) break;
    }
    return hit;
}

RC_FN RcHit rcFirstHit(vec3 o, vec3 d, vec3 bmin, vec3 bmax, ivec3 dims, float iso) {
    return rcTraceIso(o, d, bmin, bmax, dims, iso, 0);
}

#ifndef ISO_GLSL
} // namespace iso::rc
#endif

#endif
