#version 450
// isoSurface pass: one ray per pixel, the first hit with the isosurface (after the pixel's peel
// count), its colour (mono or CEIR, seed preview), shading, depth and voxel id.
#extension GL_GOOGLE_include_directive : require
#define ISO_GLSL 1
#include "iso_params.h"

layout(local_size_x = ISO_WORKGROUP_X, local_size_y = ISO_WORKGROUP_Y) in;

// Compiled-out features cost nothing: the branches on these constants fold away per variant.
layout(constant_id = ISO_SPEC_MODE) const int kMode = ISO_MODE_MONO;
layout(constant_id = ISO_SPEC_PEEL) const bool kPeel = false;
layout(constant_id = ISO_SPEC_SEEDS) const bool kSeeds = false;

layout(std140, binding = ISO_BINDING_PARAMS) uniform ParamsBlock { RenderParams params; };
#include "volume_binding.glsl"
layout(std430, binding = ISO_BINDING_COLOUR) writeonly buffer ColourBuffer { vec4 colour[]; };
layout(std430, binding = ISO_BINDING_DEPTH) writeonly buffer DepthBuffer { float depth[]; };
layout(std430, binding = ISO_BINDING_VOXEL_ID) writeonly buffer VoxelIdBuffer { uint voxelId[]; };
layout(std430, binding = ISO_BINDING_SPEED_COLOUR_MAP) readonly buffer SpeedColourMap { vec4 speedColourMap[]; };
layout(std430, binding = ISO_BINDING_PEEL_BUFFER) readonly buffer PeelBuffer { uint peelBuffer[]; };
layout(std430, binding = ISO_BINDING_SEEDS) readonly buffer Seeds { uint seedIds[]; };

vec4 rcSpeedColourEntry(int j) { return speedColourMap[j]; }
vec4 rcTransferEntry(int k) { return vec4(0.0); } // full volume rendering has its own pass
uint rcPeelAt(uint pixel) { return peelBuffer[pixel]; }
uint rcSeedAt(uint i) { return seedIds[i]; }

#include "iso_pixel.h"

void main() {
    uvec2 px = gl_GlobalInvocationID.xy;
    if (px.x >= params.image.x || px.y >= params.image.y) return;
    RcPixel result = rcIsoSurfacePixel(params, px, kMode, kPeel, kSeeds);
    uint pixel = px.x + params.image.x * px.y;
    colour[pixel] = result.colour;
    depth[pixel] = result.depth;
    voxelId[pixel] = result.voxelId;
}
