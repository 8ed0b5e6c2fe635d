// One pixel of the isoSurface pass and of the full-volume-rendering reference, shared by the GLSL
// passes and the CUDA kernels: ray generation, the hit, CEIR colouring (paper §4), seed preview
// colouring (§5.4) and shading.
//
// The includer defines, before including this file, besides ray_core.h's rcFetch:
//   vec4 rcSpeedColourEntry(int j)  entry j of the speed-colour map (ceir.h)
//   vec4 rcTransferEntry(int k)     entry k of the transfer table (ceir.h)
//   uint rcPeelAt(uint pixel)       the peel buffer: crossings to skip at this pixel
//   uint rcSeedAt(uint i)           the seed list: counts.z sorted foreground ids, then counts.w background
#ifndef ISO_PIXEL_H
#define ISO_PIXEL_H

#include "ceir.h"
#include "iso_params.h"
#include "ray_core.h"
#include "shading.h"

#ifndef ISO_GLSL
namespace iso::rc {
#endif

struct RcPixel {
    vec4 colour; // linear RGB; alpha 1 on the surface (FVR: accumulated opacity), 0 elsewhere
    float depth; // world distance to the hit, -1 for none
    uint voxelId;
};

// Binary search in the sorted ids [first, first + count) of the seed list.
RC_FN bool rcSeedListHas(uint first, uint count, uint id) {
    uint lo = first;
    uint hi = first + count;
    while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        uint v = rcSeedAt(mid);
        if (v == id) return true;
        if (v < id)
            lo = mid + 1u;
        else
            hi = mid;
    }
    return false;
}

// v' for deep CEIR (paper §4.3): march on from the hit until the value reaches iso + deltaV and
// take deltaV / Delta-l, the mean derivative over the transitional section. (The paper's text has
// Delta-l / Delta-v; speed must grow with the derivative.) If the search leaves the volume or its
// reach first, the mean derivative over what was searched is used, and where the value did not
// rise at all, the gradient's shallow estimate: a section thicker than the reach shows as slow.
// The march takes at most 1024 steps of a quarter voxel (256 voxels), whatever the reach.
RC_FN float rcDeepDerivative(RC_CONST RenderParams p, vec3 hitPos, vec3 d, ivec3 dims, float shallow) {
    float iso = p.boxMin.w;
    float target = iso + p.ceir.y;
    float step = p.ceir.z;
    float reach = p.ceir.w;
    vec3 lo = vec3(p.boxMin); // the search sees only what the crop box keeps
    vec3 hi = vec3(p.boxMax);
    float lPrev = 0.0;
    float vPrev = iso;
    int steps = min(int(reach / step), 1024);
    for (int k = 1; k <= steps; ++k) {
        float l = float(k) * step;
        vec3 q = hitPos + l * d;
        if (any(lessThan(q, lo)) || any(greaterThan(q, hi))) break;
        float v = rcSample(q, dims);
        if (v >= target) {
            float dl = lPrev + (l - lPrev) * (target - vPrev) / max(v - vPrev, 1e-30f);
            return p.ceir.y / max(dl, 1e-30f);
        }
        lPrev = l;
        vPrev = v;
    }
    return vPrev > iso && lPrev > 0.0 ? (vPrev - iso) / lPrev : shallow;
}

RC_FN RcPixel rcIsoSurfacePixel(RC_CONST RenderParams p, uvec2 px, int mode, bool peel, bool seeds) {
    RcPixel res;
    vec3 o;
    vec3 d;
    rcPrimaryRay(p, px, o, d);
    ivec3 dims = ivec3(p.dims);
    uint pixel = px.x + p.image.x * px.y;
    int skip = peel ? int(rcPeelAt(pixel)) : 0;
    RcHit hit = rcTraceIso(o, d, vec3(p.boxMin), vec3(p.boxMax), dims, p.boxMin.w, skip);
    if (hit.t < 0.0) {
        res.colour = vec4(vec3(p.background), 0.0);
        res.depth = -1.0;
        res.voxelId = ISO_NO_HIT_ID;
        return res;
    }
    res.depth = hit.t;
    res.voxelId = uint(hit.cell.x) + p.dims.x * (uint(hit.cell.y) + p.dims.y * uint(hit.cell.z));
    vec3 g = rcGradient(hit.pos, dims);
    vec3 base = vec3(p.material);
    if (mode == ISO_MODE_CEIR_SHALLOW || mode == ISO_MODE_CEIR_DEEP) {
        // v' along the unit world ray: dot(world gradient, world ray) equals dot(index gradient,
        // index ray), positive where the value rises behind the surface.
        float shallow = dot(g, d);
        float vPrime = mode == ISO_MODE_CEIR_DEEP ? rcDeepDerivative(p, hit.pos, d, dims, shallow) : shallow;
        base = rcSpeedColour(vPrime / p.ceir.x, int(p.counts.x));
    }
    if (seeds) {
        if (rcSeedListHas(0u, p.counts.z, res.voxelId))
            base = vec3(p.seedColours[0]);
        else if (rcSeedListHas(p.counts.z, p.counts.w, res.voxelId))
            base = vec3(p.seedColours[1]);
    }
    vec3 c = p.background.w != 0.0 ? rcShadeHeadlight(p, g, d, base) : base;
    res.colour = vec4(c, 1.0);
    return res;
}

// The reference CEIR approximates (paper §6): front-to-back compositing of the same transfer
// function, sampled every fvr.x world units with the opacity corrected for that step, stopping
// once the remaining transmittance is negligible.
RC_FN RcPixel rcFullVolumePixel(RC_CONST RenderParams p, uvec2 px) {
    RcPixel res;
    res.depth = -1.0;
    res.voxelId = ISO_NO_HIT_ID;
    vec3 o;
    vec3 d;
    rcPrimaryRay(p, px, o, d);
    ivec3 dims = ivec3(p.dims);
    float t0 = 0.0;
    float t1 = RC_INFINITY;
    vec3 sum = vec3(0.0);
    float transmittance = 1.0;
    if (rcClipBox(o, d, vec3(p.boxMin), vec3(p.boxMax), t0, t1)) {
        float step = p.fvr.x;
        float stepOverS0 = step / p.fvr.y;
        int n = int(min(ceil((t1 - t0) / step), 1.0e6f));
        for (int k = 0; k < n && transmittance > 1.0e-3f; ++k) {
            float t = t0 + (float(k) + 0.5f) * step;
            vec3 q = o + t * d;
            float v = rcSample(q, dims);
            vec4 tf = rcTransferAt((v - p.boxMin.w) / p.ceir.y, int(p.counts.y));
            float alpha = rcCorrectOpacity(tf.w, stepOverS0);
            if (alpha <= 0.0) continue;
            if (res.depth < 0.0) res.depth = t;
            vec3 c = vec3(tf);
            if (p.background.w != 0.0) c = rcShadeHeadlight(p, rcGradient(q, dims), d, c);
            sum += transmittance * alpha * c;
            transmittance *= 1.0f - alpha;
        }
    }
    res.colour = vec4(sum + transmittance * vec3(p.background), 1.0f - transmittance);
    return res;
}

#ifndef ISO_GLSL
} // namespace iso::rc
#endif

#endif
