#version 450
// isoSurface pass: one ray per pixel, first hit with the isosurface, shading, depth and voxel id.
#extension GL_GOOGLE_include_directive : require
#define ISO_GLSL 1
#include "iso_params.h"

layout(local_size_x = ISO_WORKGROUP_X, local_size_y = ISO_WORKGROUP_Y) in;

layout(std140, binding = ISO_BINDING_PARAMS) uniform ParamsBlock { RenderParams params; };
// Integer scans are fetched through integer formats, so every value reaches the ray core exactly
// as stored (a normalised format would round some of them); the build makes one variant per kind.
#if ISO_VOLUME_KIND == 1
layout(binding = ISO_BINDING_VOLUME) uniform isampler3D volumeTex;
#elif ISO_VOLUME_KIND == 2
layout(binding = ISO_BINDING_VOLUME) uniform usampler3D volumeTex;
#else
layout(binding = ISO_BINDING_VOLUME) uniform sampler3D volumeTex;
#endif
layout(std430, binding = ISO_BINDING_COLOUR) writeonly buffer ColourBuffer { vec4 colour[]; };
layout(std430, binding = ISO_BINDING_DEPTH) writeonly buffer DepthBuffer { float depth[]; };
layout(std430, binding = ISO_BINDING_VOXEL_ID) writeonly buffer VoxelIdBuffer { uint voxelId[]; };

float rcFetch(ivec3 p) { return float(texelFetch(volumeTex, p, 0).r); }

#include "ray_core.h"
#include "shading.h"

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= params.image.x || px.y >= params.image.y) return;
    vec3 o, d;
    rcPrimaryRay(params, px, o, d);
    ivec3 dims = ivec3(params.dims.xyz);
    RcHit hit = rcFirstHit(o, d, params.boxMin.xyz, params.boxMax.xyz, dims, params.boxMin.w);
    uint pixel = px.x + params.image.x * px.y;
    if (hit.t < 0.0) {
        colour[pixel] = vec4(params.background.rgb, 0.0);
        depth[pixel] = -1.0;
        voxelId[pixel] = ISO_NO_HIT_ID;
        return;
    }
    vec3 g = rcGradient(hit.pos, dims);
    colour[pixel] = vec4(rcShadeHeadlight(params, g, d, params.material.rgb), 1.0);
    depth[pixel] = hit.t;
    voxelId[pixel] = uint(hit.cell.x) + params.dims.x * (uint(hit.cell.y) + params.dims.y * uint(hit.cell.z));
}
