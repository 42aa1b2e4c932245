/* Every struct that crosses the host/device boundary, declared once.
 *
 * Included by the host (C++17) and by the kernels (OpenCL C 1.2). Members are
 * 4-byte scalars or arrays of them (never float3, whose OpenCL alignment is 16),
 * so both compilers lay the structs out identically; the host static_asserts
 * the sizes in host/scene/Scene.h. */
#ifndef WAVEVCM_SHARED_TYPES_H
#define WAVEVCM_SHARED_TYPES_H

#ifndef __OPENCL_C_VERSION__
#include <cstdint>
namespace wv {
typedef uint32_t uint;
typedef uint16_t ushort;
#endif

/* The BVH the kernels traverse (host/bvh/Bvh.h): BVH_WIDTH children per
 * node, their boxes stored structure-of-arrays so that one node visit tests
 * every child's slabs in a handful of vector operations
 * (kernels/geometry/bvh_traversal.h). bounds[a][i] is child i's lower bound
 * on axis a, bounds[3 + a][i] its upper bound; an empty slot has lo = +inf,
 * hi = -inf and is never hit. child[i] >= 0 is an interior node's index; a
 * leaf is ~(first packet · 8 + packets - 1): up to 8 consecutive triangle
 * packets. The root is node 0. */
#define BVH_WIDTH 8
#define BVH_LEAF_MAX_PACKETS 8
/* Entries of the traversal stack (kernels/geometry/bvh_traversal.h); the
 * host builds trees whose traversal never needs more (host/bvh/Bvh.cpp). */
#define BVH_STACK_SIZE 64
typedef struct BvhNode {
    float bounds[6][BVH_WIDTH];
    int child[BVH_WIDTH];
} BvhNode;

/* W triangles of one leaf, tested together: v[k][a][i] is coordinate a of
 * vertex k of the packet's triangle i; triangle[i] its index in the
 * BVH-ordered triangle arrays, -1 for padding (a copy of a real triangle of
 * the packet, never reported). A packet's real triangles come first.
 * Packets are four or eight triangles wide: the host builds each device's
 * tree for the width its vector unit tests at once (host/render/SceneBuffers.h,
 * trianglePacketWidth) and passes it to the program as TRIANGLE_PACKET_WIDTH
 * (geometry/intersect_triangle.h). */
#define DECLARE_TRIANGLE_PACKET(W)                                                                           \
    typedef struct TrianglePacket##W {                                                                       \
        float v[3][3][W];                                                                                    \
        int triangle[W];                                                                                     \
    } TrianglePacket##W;
DECLARE_TRIANGLE_PACKET(4)
DECLARE_TRIANGLE_PACKET(8)
#undef DECLARE_TRIANGLE_PACKET
/* The width of a tree built for no device in particular (buildBvh's default,
 * the tests'), and of a program built without TRIANGLE_PACKET_WIDTH; the
 * renderer always passes its tree's. */
#define DEFAULT_TRIANGLE_PACKET_WIDTH 8
#ifdef __OPENCL_C_VERSION__
#ifndef TRIANGLE_PACKET_WIDTH
#define TRIANGLE_PACKET_WIDTH DEFAULT_TRIANGLE_PACKET_WIDTH
#endif
#if TRIANGLE_PACKET_WIDTH == 8
typedef TrianglePacket8 TrianglePacket;
#elif TRIANGLE_PACKET_WIDTH == 4
typedef TrianglePacket4 TrianglePacket;
#else
#error "TRIANGLE_PACKET_WIDTH must be 4 or 8"
#endif
#endif

/* The camera. A pixel (x, y) with sub-pixel jitter (u, v) maps to the image
 * point (2(x+u)/W - 1)·right + (1 - 2(y+v)/H)·up. For a pinhole camera that
 * is the direction forward + it, right and up scaled by tan(fov/2) so that
 * the image plane is at distance 1; for an orthographic one (compiled with
 * -DORTHOGRAPHIC_CAMERA) the ray's origin is position + it, in scene units,
 * and its direction forward. Row 0 is the top of the image. */
typedef struct Camera {
    float position[3];
    float imagePlaneArea; /* area of the image plane at distance 1 (camera importance) */
    float forward[3];
    int width;
    float right[3];
    int height;
    float up[3];
    float pad;
} Camera;

/* BSDF lobes a material has; kernels evaluate only the lobes present. */
#define LOBE_DIFFUSE 1u
#define LOBE_GGX_REFLECTION 2u
#define LOBE_GGX_TRANSMISSION 4u
#define LOBE_DELTA_REFLECTION 8u
#define LOBE_DELTA_TRANSMISSION 16u
#define LOBE_GGX_COAT 32u   /* KHR_materials_clearcoat: a GGX reflection on top of the others */
#define LOBE_DELTA_COAT 64u /* the same, smooth */
#define LOBE_SHEEN 128u     /* KHR_materials_sheen: fibres over the diffuse and reflection lobes */
#define LOBE_DIFFUSE_TRANSMISSION 256u /* KHR_materials_diffuse_transmission: Lambert through the surface */
#define LOBES_ALL 511u

/* The glTF metallic-roughness model with KHR_materials_specular,
 * _transmission, _diffuse_transmission, _ior, _volume, _clearcoat, _sheen,
 * _anisotropy and _emissive_strength folded in;
 * see docs/scenes.md, "Materials", for the mapping. */
typedef struct Material {
    float baseColor[3];
    float metallic;
    float emission[3]; /* emitted radiance: emissiveFactor × emissiveStrength */
    float roughness;   /* perceptual roughness; GGX alpha = roughness² */
    float specularColor[3];
    float specular; /* KHR_materials_specular specularFactor */
    float ior;
    float transmission;
    uint lobes;          /* LOBE_* bits */
    int thinWalled;      /* 1: transmission without refraction (no KHR_materials_volume) */
    float attenuationColor[3];
    float attenuationDistance; /* KHR_materials_volume; 0 = no absorption */
    int baseColorTexture;      /* 1 + its index in the texture table; 0: none (baseColor alone) */
    int metallicRoughnessTexture; /* the same; its G scales roughness, its B metallic (linear) */
    int normalTexture;         /* the same; tangent-space normals (materials/normal_map.h) */
    float normalScale;         /* glTF normalTexture.scale: the map's x and y times this */
    int alphaMode;             /* ALPHA_* (materials/alpha.h) */
    float alphaCutoff;         /* MASK: opaque where alpha >= this */
    float baseColorAlpha;      /* baseColorFactor's alpha; the base-colour texture's A multiplies it */
    int emissiveTexture;       /* 1 + its index in the texture table; its RGB scales emission (materials/emission.h) */
    int transmissionTexture;   /* the same; its R scales transmission (KHR_materials_transmission) */
    int doubleSided;           /* glTF doubleSided: an emitter emits from both faces (else its front only) */
    float clearcoat;           /* KHR_materials_clearcoat clearcoatFactor; 0: no coat */
    float clearcoatRoughness;  /* clearcoatRoughnessFactor; the coat's GGX alpha = this² */
    int clearcoatTexture;      /* 1 + its index in the texture table; its R scales clearcoat */
    int clearcoatRoughnessTexture; /* the same; its G scales clearcoatRoughness */
    float sheenColor[3];       /* KHR_materials_sheen sheenColorFactor; black: no sheen */
    float sheenRoughness;      /* sheenRoughnessFactor; the fibres' alpha = this² (materials/sheen.h) */
    int sheenColorTexture;     /* 1 + its index in the texture table; its RGB (sRGB-decoded) scales sheenColor */
    int sheenRoughnessTexture; /* the same; its alpha scales sheenRoughness */
    int specularTexture;       /* the same; its alpha scales specular (KHR_materials_specular) */
    int specularColorTexture;  /* the same; its RGB (sRGB-decoded) scales specularColor */
    float diffuseTransmission; /* KHR_materials_diffuse_transmission diffuseTransmissionFactor; 0: none */
    float diffuseTransmissionColor[3]; /* diffuseTransmissionColorFactor */
    int diffuseTransmissionTexture;      /* 1 + its index in the texture table; its alpha scales diffuseTransmission */
    int diffuseTransmissionColorTexture; /* the same; its RGB (sRGB-decoded) scales diffuseTransmissionColor */
    float anisotropy;          /* KHR_materials_anisotropy anisotropyStrength; 0: isotropic */
    float anisotropyRotation[2]; /* cos and sin of anisotropyRotation (from the tangent towards the bitangent) */
    int anisotropyTexture;     /* 1 + its index in the texture table; its RG a direction, its B scales anisotropy */
    int pad[12]; /* to 256 bytes: callgrind counts shade_bidirectional 19 instructions per item
                    fewer (vcm) than at 208 or 224 (docs/performance.md, "Vectorization on PoCL") */
} Material;

/* glTF alphaMode. */
#define ALPHA_OPAQUE 0
#define ALPHA_MASK 1
#define ALPHA_BLEND 2

/* How a texture repeats outside [0, 1] (glTF sampler wrapS / wrapT). */
#define WRAP_REPEAT 0
#define WRAP_CLAMP 1
#define WRAP_MIRROR 2

/* A texture of the scene: width × height linear RGB texels, row 0 at v = 0,
 * stored as float4 from texel `offset` of one buffer (kernels/materials/texture.h),
 * looked up at (u', v') = (t[0] u + t[1] v + t[2], t[3] u + t[4] v + t[5]),
 * t = uvTransform (KHR_texture_transform; the identity without it). */
typedef struct TextureInfo {
    int offset;
    int width, height;
    int wrapS, wrapT;
    float uvTransform[6];
    int texCoord; /* the set it reads: 0 TEXCOORD_0, 1 TEXCOORD_1 */
} TextureInfo;

#define LIGHT_POINT 0
#define LIGHT_SPOT 1
#define LIGHT_DIRECTIONAL 2
#define LIGHT_TRIANGLE 3
#define LIGHT_BACKGROUND 4

/* One light of the scene's light table, in world space. The loader fills the
 * punctual lights (KHR_lights_punctual); the renderer appends one entry per
 * emissive triangle and one for the background, and sets the selection
 * probabilities (proportional to emitted power). */
typedef struct Light {
    float position[3];  /* point, spot */
    int type;           /* LIGHT_* */
    float direction[3]; /* unit vector the light points along (spot, directional) */
    float cosInnerCone;
    float emission[3];  /* intensity W/sr (point, spot); irradiance (directional);
                           radiance (triangle, background) */
    float cosOuterCone;
    int triangle;       /* BVH-ordered triangle index (triangle lights) */
    float area;         /* triangle area */
    float pmf;          /* probability of selecting this light */
    int sides;          /* triangle lights: 1 emits from its front face (along its normal), 2 from both
                           (a doubleSided material); their emission densities carry 1/sides */
} Light;

/* A surface point as a kernel built it (SurfaceHit, geometry/surface.h),
 * stored for later kernels so that they need not rebuild it from the
 * triangle: one 64-byte cache line. */
typedef struct SurfaceRecord {
    float position[3];
    int frontSide;            /* SurfaceHit.frontSide */
    float positionError[3];   /* SurfaceHit.pError */
    float pad0;
    float geometricNormal[3]; /* SurfaceHit.ngF */
    float pad1;
    float shadingNormal[3];   /* SurfaceHit.nsF */
    float pad2;
} SurfaceRecord;

/* A vertex of a light sub-path, stored for vertex connection (bpt, vcm):
 * everything a camera vertex needs to connect to it, 128 bytes. Its surface
 * is stored as shade_light built it, not rebuilt from the triangle per
 * connection (that took about a tenth of connect_vertices: docs/performance.md,
 * "Where the time goes"); the triangle and barycentrics remain for its material and
 * textures. Vertices of one light path form a list from its last vertex
 * back (prev). */
typedef struct LightVertex {
    SurfaceRecord surface;
    float throughput[3]; /* of the light path up to and including this vertex's incoming segment */
    float dVCM;
    float toLight[3];    /* unit direction back along the light path */
    float dVC;
    float dVM;
    int pathLength;      /* segments from the light to this vertex */
    int triangle;        /* BVH-ordered: material, textures */
    int prev;            /* previous stored vertex of the same light path, -1 at its first */
    float b1;            /* barycentrics of the hit */
    float b2;
    float continuation;  /* Russian roulette survival probability of its BSDF (in merges' and connections' pdfs) */
    int number;          /* of its light path's stored vertices, counting from 1 at the light's end */
} LightVertex;

/* A light vertex as vertex merging reads it (merge.cl), copied by the hash
 * grid's build into bucket order (hash_grid.h): a query tests the position
 * and finds the rest on the same 64-byte cache line, and the vertices of one
 * bucket lie one after another. */
typedef struct MergeVertex {
    float position[3];
    int pathLength;
    float toLight[3];
    float dVCM;
    float throughput[3];
    float dVM;
    float continuation;
    float pad[3];
} MergeVertex;

#ifdef __OPENCL_C_VERSION__
/* What the light-vertex buffer holds: LightVertex records where camera
 * paths connect to them (VERTEX_CONNECTION: bpt, vcm); with merging only
 * (ppm, bpm) the MergeVertex records that merging reads, half the bytes,
 * which the hash grid's build then only moves into bucket order. */
#ifdef VERTEX_CONNECTION
typedef LightVertex StoredLightVertex;
#else
typedef MergeVertex StoredLightVertex;
#endif
#endif

/* Scene-wide constants the kernels need besides the arrays. */
typedef struct SceneInfo {
    float center[3]; /* bounding sphere, for infinite lights */
    float radius;
    int lightCount;
    int backgroundLight; /* index in the light table, -1 if none */
    /* The environment map (kernels/lights/environment.h), if the background
     * has one: texels, its turn about +y (a fraction of a full turn), and
     * the factor that makes luminance · sin θ a density over (u, v). */
    int envWidth, envHeight;
    float envRotation;
    float envPdfScale;
    int pad[2];
} SceneInfo;

#ifndef __OPENCL_C_VERSION__
} /* namespace wv */
#endif

#endif
