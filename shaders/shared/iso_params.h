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

#define ISO_NO_HIT_ID 0xFFFFFFFFu

#ifndef ISO_GLSL
namespace iso::rc {
#endif

// The camera arrives already mapped into index space (sample (i,j,k) at integer (i,j,k)), so the
// traversal never leaves it; t along a ray stays the world distance because the index-space
// direction is the image of a unit world vector.
struct RenderParams {
    vec4 eye;        // xyz: eye in index space; w: 1 for orthographic
    vec4 forward;    // xyz: index-space image of the unit world view direction; w: half-extent along right
    vec4 right;      // xyz: image of the unit world right vector; w: half-extent along up
    vec4 up;         // xyz: image of the unit world up vector
    vec4 toIndex0;   // rows of the linear part of world -> index, for world-space gradients
    vec4 toIndex1;
    vec4 toIndex2;
    vec4 boxMin;     // xyz: crop box in index space (within [0, n-1]); w: isovalue (fetches return the scan's own values)
    vec4 boxMax;     // xyz: crop box max; w: unused
    uvec4 dims;      // xyz: samples per axis
    uvec4 image;     // xy: image size in pixels
    vec4 material;   // rgb: surface colour; a: ambient
    vec4 lighting;   // x: diffuse, y: specular, z: shininess
    vec4 background; // rgb: background colour
};

#ifndef ISO_GLSL
} // namespace iso::rc
#endif

#endif
