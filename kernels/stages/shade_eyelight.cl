/* shade_eyelight (`-a el`): radiance = |cos| between the primary ray and the
 * shading normal at the first hit (vertex normals and normal maps included;
 * 0 where the ray escapes). Exercises scene, BVH, kernels and output before
 * any light transport. */
#include "core/queues.h"
#include "materials/surface_bsdf.h"
#include "transport/path_state.h"

__kernel void shade_eyelight(RENDER_KERNEL_PARAMS)
{
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    int slot = queue_item(queueItems, queueCounters, params.capacity, QUEUE_HITS, get_global_id(0));
    if (slot >= 0) {
        vec3 w = v3_neg(v3_normalize(load_vec3(rayDirections, slot)));
        SurfaceHit hit = scene_surface_hit(&b, hitTriangle[slot], load_vec2(hitBary, slot), w);
        float value = fabs(v3_dot(w, hit.nsF));
        add_vec3(pixelRadiance, pathPixel[slot], v3s(value));
    }
}
