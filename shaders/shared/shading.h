// Primary rays and headlight Blinn-Phong shading, shared by the isosurface passes of every backend.
#ifndef ISO_SHADING_H
#define ISO_SHADING_H

#include "iso_params.h"

#ifndef ISO_GLSL
namespace iso::rc {
#endif

// Ray through the centre of pixel px, in index space (see RenderParams). x runs right, y down.
RC_FN void rcPrimaryRay(RC_CONST RenderParams p, uvec2 px, RC_OUT(vec3) o, RC_OUT(vec3) d) {
    float u = ((float(px.x) + 0.5f) / float(p.image.x) * 2.0f - 1.0f) * p.forward.w;
    float v = (1.0f - (float(px.y) + 0.5f) / float(p.image.y) * 2.0f) * p.right.w;
    vec3 fwd = vec3(p.forward);
    vec3 right = vec3(p.right);
    vec3 up = vec3(p.up);
    if (p.eye.w != 0.0) {
        o = vec3(p.eye) + u * right + v * up;
        d = fwd;
    } else {
        // forward, right and up are images of orthonormal world vectors, so the world length of
        // fwd + u*right + v*up is sqrt(1 + u^2 + v^2): dividing by it keeps t a world distance.
        o = vec3(p.eye);
        d = (fwd + u * right + v * up) / sqrt(1.0f + u * u + v * v);
    }
}

// World-space gradient from an index-space one: the transpose of world -> index applied to g.
RC_FN vec3 rcWorldGradient(RC_CONST RenderParams p, vec3 g) {
    return g.x * vec3(p.toIndex0) + g.y * vec3(p.toIndex1) + g.z * vec3(p.toIndex2);
}

// Headlight (light at the eye), two-sided: with L = V = -ray, n.L = n.V = n.H, so only the
// cosine between the surface normal and the ray is needed. dot(worldGrad, worldDir) equals
// dot(indexGrad, indexDir), so the index-space ray can be used directly.
RC_FN vec3 rcShadeHeadlight(RC_CONST RenderParams p, vec3 indexGrad, vec3 indexDir, vec3 base) {
    float gl = length(rcWorldGradient(p, indexGrad));
    float cosine = gl > 0.0 ? abs(dot(indexGrad, indexDir)) / gl : 1.0f;
    cosine = min(cosine, 1.0f);
    float spec = p.lighting.y * pow(cosine, p.lighting.z);
    return base * (p.material.a + p.lighting.x * cosine) + vec3(spec);
}

#ifndef ISO_GLSL
} // namespace iso::rc
#endif

#endif
