// Parameters of the isosurface passes, shared by GLSL (std140 uniform block), C++ and CUDA.
// Every member is a 16-byte vector, so std140 and the C++ layout agree; static_asserts in
// engine/render/iso_params.cpp keep it that way.
#ifndef ISO_PARAMS_H
#define ISO_PARAMS_H

#include "portable.h"

#define ISO_WORKGROUP_X 8
#define ISO_WORKGROUP_Y 8

// Descriptor bindings of the isoSurface pass.
#define ISO_BINDING_PARAMS 0
#define ISO_BINDING_VOLUME 1
#define ISO_BINDING_COLOUR 2
#define ISO_BINDING_DEPTH 3
#define ISO_BINDING_VOXEL_ID 4
#define ISO_BINDING_SPEED_COLOUR_MAP 5 // vec4[m + 1], CEIR modes
#define ISO_BINDING_TRANSFER_TABLE 6   // vec4[entries], full volume rendering
#define ISO_BINDING_PEEL_BUFFER 7      // uint per pixel, when peeling windows exist
#define ISO_BINDING_SEEDS 8            // sorted foreground ids, then sorted background ids

// Rendering modes (the isoSurface pass's first specialization constant).
#define ISO_MODE_MONO 0
#define ISO_MODE_CEIR_SHALLOW 1
#define ISO_MODE_CEIR_DEEP 2
#define ISO_MODE_FVR 3

// Specialization constant ids: an unused feature is compiled out of the pass.
#define ISO_SPEC_MODE 0
#define ISO_SPEC_PEEL 1
#define ISO_SPEC_SEEDS 2

#define ISO_NO_HIT_ID 0xFFFFFFFFu

#ifndef ISO_GLSL
namespace iso::rc {
#endif

// The camera arrives already mapped into index space (sample (i,j,k) at integer (i,j,k)), so the
// traversal never leaves it; t along a ray stays the world distance because the index-space
// direction is the image of a unit world vector.
struct RenderParams {
    vec4 eye;      // xyz: eye in index space; w: 1 for orthographic
    vec4 forward;  // xyz: index-space image of the unit world view direction; w: half-extent along right
    vec4 right;    // xyz: image of the unit world right vector; w: half-extent along up
    vec4 up;       // xyz: image of the unit world up vector
    vec4 toIndex0; // rows of the linear part of world -> index, for world-space gradients
    vec4 toIndex1;
    vec4 toIndex2;
    vec4 boxMin; // xyz: crop box in index space (within [0, n-1]); w: isovalue (fetches return the scan's own
                 // values)
    vec4 boxMax; // xyz: crop box max; w: unused
    uvec4 dims;  // xyz: samples per axis
    uvec4 image; // xy: image size in pixels
    vec4 material;   // rgb: surface colour; a: ambient
    vec4 lighting;   // x: diffuse, y: specular, z: shininess
    vec4 background; // rgb: background colour; w: 1 to shade, 0 for the material colour alone
    vec4 ceir;       // x: densityFactor, y: deltaV, z: deep-search step (world), w: deep-search reach (world)
    vec4 fvr;        // x: sampling step (world), y: standard sample distance s0 = deltaV / densityFactor
    uvec4 counts; // x: speed-colour map intervals m, y: transfer table entries, z, w: fore/background seeds
    vec4 seedColours[2]; // rgb of hits in foreground and background seed cells
};

#ifndef ISO_GLSL
} // namespace iso::rc
#endif

#endif
