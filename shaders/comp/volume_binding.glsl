// The scan, bound for texel fetches. Integer scans use integer formats so that every value reaches
// the ray core exactly as stored (a normalised format would round some); the build makes one
// variant of each pass per kind: ISO_VOLUME_KIND 0 float, 1 signed, 2 unsigned.
#if ISO_VOLUME_KIND == 1
layout(binding = ISO_BINDING_VOLUME) uniform isampler3D volumeTex;
#elif ISO_VOLUME_KIND == 2
layout(binding = ISO_BINDING_VOLUME) uniform usampler3D volumeTex;
#else
layout(binding = ISO_BINDING_VOLUME) uniform sampler3D volumeTex;
#endif

float rcFetch(ivec3 p) { return float(texelFetch(volumeTex, p, 0).r); }
