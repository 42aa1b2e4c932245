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
    for (int m : triangleMaterial) {
        f.lobes |= materials[m].lobes;
        const float* e = materials[m].emission;
        if (e[0] > 0 || e[1] > 0 || e[2] > 0) f.emissiveTriangles = true;
        if (materials[m].alphaMode != ALPHA_OPAQUE) f.alphaTest = true;
    }
    for (const Light& l : lights) {
        f.pointLights |= l.type == LIGHT_POINT;
        f.spotLights |= l.type == LIGHT_SPOT;
        f.directionalLights |= l.type == LIGHT_DIRECTIONAL;
    }
    f.environmentMap = !environment.empty();
    f.textures = !textures.empty();
    f.normalMaps = !tangents.empty();
    f.background = f.environmentMap || background.x > 0 || background.y > 0 || background.z > 0;
    return f;
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
    if (environmentMap) o += " -DHAS_ENVIRONMENT_MAP";
    if (textures) o += " -DHAS_TEXTURES";
    if (normalMaps) o += " -DHAS_NORMAL_MAPS";
    if (alphaTest) o += " -DHAS_ALPHA_TEST";
    return o;
}

static void store(float dst[3], Vec3 v) { dst[0] = v.x; dst[1] = v.y; dst[2] = v.z; }

Camera makeCamera(const CameraView& view, int width, int height)
{
    Vec3 forward = normalize(view.forward);
    Vec3 right = normalize(cross(forward, view.up));
    Vec3 up = cross(right, forward);
    float tanHalf = std::tan(0.5f * view.yfov);
    float aspect = float(width) / float(height);
    Camera c{};
    store(c.position, view.position);
    store(c.forward, forward);
    store(c.right, right * (tanHalf * aspect));
    store(c.up, up * tanHalf);
    c.width = width;
    c.height = height;
    c.imagePlaneArea = 4.0f * tanHalf * tanHalf * aspect;
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
