#version 450
// fullVolume pass: the full-volume-rendering reference (paper §6) with the same local transfer
// function as CEIR, front to back with opacity correction and early termination.
#extension GL_GOOGLE_include_directive : require
#define ISO_GLSL 1
#include "iso_params.h"

layout(local_size_x = ISO_WORKGROUP_X, local_size_y = ISO_WORKGROUP_Y) in;

layout(std140, binding = ISO_BINDING_PARAMS) uniform ParamsBlock { RenderParams params; };
#include "volume_binding.glsl"
layout(std430, binding = ISO_BINDING_COLOUR) writeonly buffer ColourBuffer { vec4 colour[]; };
layout(std430, binding = ISO_BINDING_DEPTH) writeonly buffer DepthBuffer { float depth[]; };
layout(std430, binding = ISO_BINDING_VOXEL_ID) writeonly buffer VoxelIdBuffer { uint voxelId[]; };
layout(std430, binding = ISO_BINDING_TRANSFER_TABLE) readonly buffer TransferTable { vec4 transferTable[]; };

vec4 rcSpeedColourEntry(int j) { return vec4(0.0); } // CEIR lives in the isoSurface pass
vec4 rcTransferEntry(int k) { return transferTable[k]; }
uint rcPeelAt(uint pixel) { return 0u; }
uint rcSeedAt(uint i) { return 0u; }

#include "iso_pixel.h"

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= params.image.x || px.y >= params.image.y) return;
    RcPixel result = rcFullVolumePixel(params, px);
    uint pixel = px.x + params.image.x * px.y;
    colour[pixel] = result.colour;
    depth[pixel] = result.depth;
    voxelId[pixel] = result.voxelId;
}
