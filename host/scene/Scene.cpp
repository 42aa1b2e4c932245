#include "Scene.h"

#include <algorithm>

#include <cmath>

namespace wv {

Bounds Scene::bounds() const
{
    Bounds b;
    for (const Vec3& v : vertices) b.extend(v);
    return b;
}

SceneFeatures Scene::features() const
{
    SceneFeatures f;
    f.vertexNormals = !normals.empty();
    f.tangents = !tangents.empty();
    for (int m : triangleMaterial) {
        f.lobes |= materials[m].lobes;
        const float* e = materials[m].emission;
        if (e[0] > 0 || e[1] > 0 || e[2] > 0) {
            f.emissiveTriangles = true;
            if (materials[m].emissiveTexture > 0) f.emissiveTextures = true;
        }
        if (materials[m].alphaMode != ALPHA_OPAQUE) f.alphaTest = true;
        const Material& mat = materials[m];
        if (!mat.thinWalled && mat.attenuationDistance > 0 && (mat.lobes & (LOBE_GGX_TRANSMISSION | LOBE_DELTA_TRANSMISSION | LOBE_DIFFUSE_TRANSMISSION)) &&
            std::min({mat.attenuationColor[0], mat.attenuationColor[1], mat.attenuationColor[2]}) < 1)
            f.volumeAbsorption = true;
        f.normalMaps |= f.tangents && mat.normalTexture > 0;
        f.anisotropy |= mat.anisotropy > 0;
    }
    for (const Light& l : lights) {
        f.pointLights |= l.type == LIGHT_POINT;
        f.spotLights |= l.type == LIGHT_SPOT;
        f.directionalLights |= l.type == LIGHT_DIRECTIONAL;
    }
    f.environmentMap = !environment.empty();
    if (f.environmentMap) f.environmentSize = std::max(environment.image.width, environment.image.height);
    f.textures = !textures.empty();
    f.texCoord1 = !uvs1.empty();
    f.vertexColors = !colors.empty();
    f.orthographicCamera = camera.orthographic;
    f.background = f.environmentMap || background.x > 0 || background.y > 0 || background.z > 0;
    return f;
}

int binarySearchSteps(int count)
{
    int steps = 0;
    while (steps < 31 && (1 << steps) < count) ++steps;
    return std::min(31, (steps + 3) / 4 * 4);
}

bool Scene::hasLight() const
{
    if (!lights.empty() || std::max({background.x, background.y, background.z}) > 0) return true;
    if (!environment.empty() && environment.strength > 0 &&
        *std::max_element(environment.image.rgb.begin(), environment.image.rgb.end()) > 0)
        return true;
    for (int m : triangleMaterial)
        if (std::max({materials[m].emission[0], materials[m].emission[1], materials[m].emission[2]}) > 0) return true;
    return false;
}

std::string SceneFeatures::buildOptions() const
{
    std::string o;
    if (vertexNormals) o += " -DHAS_VERTEX_NORMALS";
    o += " -DSCENE_LOBES=" + std::to_string(lobes) + "u";
    if (pointLights || spotLights) o += " -DHAS_POINT_LIGHTS"; // spot = point with a cone
    if (directionalLights) o += " -DHAS_DIRECTIONAL_LIGHTS";
    if (emissiveTriangles) o += " -DHAS_EMISSIVE_TRIANGLES";
    if (background) o += " -DHAS_BACKGROUND";
    if (environmentMap)
        o += " -DHAS_ENVIRONMENT_MAP -DENV_CDF_STEPS=" + std::to_string(binarySearchSteps(environmentSize));
    if (textures) o += " -DHAS_TEXTURES";
    if (normalMaps) o += " -DHAS_NORMAL_MAPS";
    if (tangents || normalMaps) o += " -DHAS_TANGENTS";
    if (anisotropy) o += " -DHAS_ANISOTROPY";
    if (alphaTest) o += " -DHAS_ALPHA_TEST";
    if (emissiveTextures) o += " -DHAS_EMISSIVE_TEXTURES";
    if (texCoord1) o += " -DHAS_TEXCOORD1";
    if (volumeAbsorption) o += " -DHAS_VOLUME_ABSORPTION";
    if (vertexColors) o += " -DHAS_VERTEX_COLORS";
    if (orthographicCamera) o += " -DORTHOGRAPHIC_CAMERA";
    return o;
}

Vec3 Texture::sample(float u0, float v0) const
{
    const std::array<float, 6>& t = uvTransform;
    float u = t[0] * u0 + t[1] * v0 + t[2], v = t[3] * u0 + t[4] * v0 + t[5];
    float x = std::clamp(u, -1e6f, 1e6f) * float(image.width) - 0.5f;
    float y = std::clamp(v, -1e6f, 1e6f) * float(image.height) - 0.5f;
    float fx = std::floor(x), fy = std::floor(y), ax = x - fx, ay = y - fy;
    auto wrap = [](int i, int n, int mode) {
        if (mode == WRAP_CLAMP) return std::clamp(i, 0, n - 1);
        int period = mode == WRAP_MIRROR ? 2 * n : n;
        int m = i % period;
        m = m < 0 ? m + period : m;
        return mode == WRAP_MIRROR && m >= n ? period - 1 - m : m;
    };
    auto texel = [&](int i, int j) {
        size_t p = size_t(wrap(j, image.height, wrapT)) * size_t(image.width) + size_t(wrap(i, image.width, wrapS));
        return Vec3(image.rgb[3 * p], image.rgb[3 * p + 1], image.rgb[3 * p + 2]);
    };
    int i = int(fx), j = int(fy);
    Vec3 top = texel(i, j) * (1 - ax) + texel(i + 1, j) * ax;
    Vec3 bottom = texel(i, j + 1) * (1 - ax) + texel(i + 1, j + 1) * ax;
    return top * (1 - ay) + bottom * ay;
}

static void store(float dst[3], Vec3 v) { dst[0] = v.x; dst[1] = v.y; dst[2] = v.z; }

Camera makeCamera(const CameraView& view, int width, int height)
{
    Vec3 forward = normalize(view.forward);
    Vec3 right = normalize(cross(forward, view.up));
    Vec3 up = cross(right, forward);
    // The image's half-height: at distance 1 for a perspective camera, in
    // scene units for an orthographic one (kernels/lights/camera.h).
    float halfHeight = view.orthographic ? view.ymag : std::tan(0.5f * view.yfov);
    float aspect = float(width) / float(height);
    Camera c{};
    store(c.position, view.position);
    store(c.forward, forward);
    store(c.right, right * (halfHeight * aspect));
    store(c.up, up * halfHeight);
    c.width = width;
    c.height = height;
    c.imagePlaneArea = 4.0f * halfHeight * halfHeight * aspect;
    return c;
}

CameraView framingCamera(const Bounds& bounds, float aspectRatio)
{
    CameraView v;
    Vec3 e = bounds.extent();
    float radius = 0.5f * length(e);
    v.yfov = 0.8f;
    v.aspectRatio = aspectRatio;
    // Distance at which the bounding sphere fits the vertical field of view.
    float distance = radius / std::sin(0.5f * v.yfov);
    v.position = bounds.center() + Vec3(0, 0, distance);
    v.forward = {0, 0, -1};
    v.up = {0, 1, 0};
    return v;
}

} // namespace wv
