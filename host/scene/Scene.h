// The scene as the renderer sees it: flat world-space triangles, materials,
// lights, a camera and the set of features the kernels must be compiled for.
#pragma once

#include "../../kernels/interface/shared_types.h"
#include "../Vec3.h"
#include "../image/Image.h"

#include <array>
#include <string>
#include <vector>

namespace wv {

// Layout checks for the structs shared with the kernels (see shared_types.h).
static_assert(sizeof(BvhNode) == 7 * 4 * BVH_WIDTH, "BvhNode layout");
static_assert(sizeof(TrianglePacket4) == 40 * 4 && sizeof(TrianglePacket8) == 40 * 8, "TrianglePacket layout");
static_assert(sizeof(Camera) == 64, "Camera layout");
static_assert(sizeof(Material) == 256, "Material layout");
static_assert(sizeof(TextureInfo) == 48, "TextureInfo layout");
static_assert(sizeof(Light) == 64, "Light layout");
static_assert(sizeof(SceneInfo) == 48, "SceneInfo layout");
static_assert(sizeof(SurfaceRecord) == 64, "SurfaceRecord layout");
static_assert(sizeof(LightVertex) == 128, "LightVertex layout");
static_assert(sizeof(MergeVertex) == 64, "MergeVertex layout");

// An equirectangular environment map (--environment): the background's
// radiance by direction, in the frame kernels/lights/environment.h describes.
struct EnvironmentMap {
    std::string path;
    Image image;          // linear RGB; row 0 looks straight up (+y)
    float strength = 1;   // radiance scale
    float rotation = 0;   // turn about +y, degrees
    bool empty() const { return image.rgb.empty(); }
};

// A texture: linear values (colour sRGB-decoded from the file, data as stored), row 0 at v = 0.
struct Texture {
    std::string name;
    Image image;
    int wrapS = WRAP_REPEAT, wrapT = WRAP_REPEAT;
    // KHR_texture_transform as an affine map of the texture coordinates (TextureInfo::uvTransform).
    std::array<float, 6> uvTransform{1, 0, 0, 0, 1, 0};
    int texCoord = 0; // which set it reads: TEXCOORD_0 or _1

    // The bilinear lookup at texture coordinates (u, v), as kernels/materials/texture.h does it.
    Vec3 sample(float u, float v) const;
};

// A camera as the glTF file describes it, before an image size is chosen.
struct CameraView {
    Vec3 position{0, 0, 0};
    Vec3 forward{0, 0, -1};
    Vec3 up{0, 1, 0};
    float yfov = 0.7f;        // radians (perspective)
    float aspectRatio = 0.0f; // width / height; 0 = not given by the file
    bool orthographic = false; // glTF's orthographic camera: parallel rays over ...
    float ymag = 1.0f;         // ... [-ymag, ymag] vertically (and ymag × aspect horizontally)
};

// Which kernel code the scene needs; becomes -D options of the kernel build.
struct SceneFeatures {
    bool vertexNormals = false;
    unsigned lobes = 0; // union of Material::lobes
    bool pointLights = false, spotLights = false, directionalLights = false;
    bool emissiveTriangles = false;
    bool background = false;
    bool environmentMap = false; // the background's radiance comes from a map
    int environmentSize = 0;     // its larger side, in texels
    bool textures = false;       // some material has a texture
    bool normalMaps = false;     // some material has a normal texture, and the triangles tangents
    bool tangents = false;       // the triangles have tangents (Scene::tangents: normal maps, anisotropy)
    bool anisotropy = false;     // some material is anisotropic (KHR_materials_anisotropy)
    bool alphaTest = false;      // some material's alphaMode is MASK or BLEND: rays test alpha
    bool emissiveTextures = false; // some emitting triangle's material has an emissive texture
    bool texCoord1 = false;      // some texture reads TEXCOORD_1 (Scene::uvs1)
    bool volumeAbsorption = false; // some refracting solid absorbs (KHR_materials_volume attenuation)
    bool vertexColors = false;   // some primitive has COLOR_0 (Scene::colors)
    bool orthographicCamera = false; // the camera rendered is orthographic (kernels/lights/camera.h)

    std::string buildOptions() const;
};

// Steps of a kernel's binary search over `count` entries (kernels/core/sampling.h,
// cdf_bin): enough bits for the largest index, rounded up to a multiple of 4, so
// that scenes whose counts differ a little share one program and its cache
// entries; a step costs a few instructions, where the 31 steps that cover any
// count cost shade 3-5 % of its rate.
int binarySearchSteps(int count);

struct Scene {
    std::string path;
    // Three vertices per triangle, world space.
    std::vector<Vec3> vertices;
    // Three per triangle if any primitive has NORMAL (geometric normals fill the
    // others), empty otherwise.
    std::vector<Vec3> normals;
    std::vector<int> triangleMaterial;
    std::vector<Material> materials;
    std::vector<Light> lights; // punctual lights only; see render/LightTable.h
    Vec3 background{0, 0, 0}; // uniform background radiance (scene extras.background)
    EnvironmentMap environment; // replaces the uniform background when it has texels
    std::vector<Texture> textures; // Material::baseColorTexture, ::metallicRoughnessTexture, ::normalTexture
    // TEXCOORD_0 of every triangle's corners (u, v per corner: 6 floats per
    // triangle) when the scene has textures, else empty.
    std::vector<float> uvs;
    // TEXCOORD_1 likewise, when some texture reads that set, else empty.
    std::vector<float> uvs1;
    // COLOR_0 (linear RGBA, multiplying the base colour and its alpha) of
    // every triangle's corners when some primitive has it (opaque white for
    // the others), else empty.
    std::vector<std::array<float, 4>> colors;
    // Tangent frames of every triangle's corners for normal maps and
    // anisotropy (three per triangle: x, y, z along +u, handedness w = ±1,
    // the bitangent being cross(n, t)·w), zero where the material has none;
    // empty when no material has a normal map or anisotropy.
    std::vector<std::array<float, 4>> tangents;
    CameraView camera;         // the one rendered: the file's first camera by default
    bool cameraFromFile = false;
    std::vector<CameraView> cameras; // every camera of the file, in node order (--camera N)
    // Where the scene's coordinates start in the file's: the loader moves a
    // scene that lies far from the origin (compared with its size) so that
    // its centre is at the origin (file position = position + origin).
    double origin[3] = {0, 0, 0};
    std::vector<std::string> warnings;

    size_t triangleCount() const { return triangleMaterial.size(); }
    // Whether anything emits: a punctual light, a triangle whose material
    // emits, or the background.
    bool hasLight() const;
    Bounds bounds() const;
    SceneFeatures features() const;
};

// The pinhole camera for an image of width × height pixels.
Camera makeCamera(const CameraView& view, int width, int height);

// A camera looking at the scene's bounds along -z, used when the file has none.
CameraView framingCamera(const Bounds& bounds, float aspectRatio);

} // namespace wv
