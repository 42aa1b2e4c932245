/* escaped: camera rays that left the scene see the background light,
 * MIS-weighted against the other techniques that find it (power heuristic
 * against next-event estimation for pt, the recursive weights for the
 * bidirectional algorithms); light paths that leave just end. */
#include "core/nan_policy.h"
#include "core/queues.h"
#include "lights/lights.h"
#include "transport/mis.h"
#include "transport/path_state.h"

__kernel void escaped(RENDER_KERNEL_PARAMS)
{
    int slot = queue_item(queueItems, queueCounters, params.capacity, QUEUE_ESCAPED, get_global_id(0));
    int rejected = 0;
#if defined(HAS_BACKGROUND) && !defined(EYE_LIGHT)
    if (slot >= 0 && params.cameraPaths && scene->backgroundLight >= 0) {
        __global const Light* bg = &lights[scene->backgroundLight];
        Environment env = {envRadiance, envMarginalCdf, envConditionalCdf};
        float lightPdf; /* of light sampling picking this direction */
        vec3 radiance = background_radiance(bg, scene, &env, load_vec3(rayDirections, slot), &lightPdf);
        float w = 1.0f; /* seen directly, or through delta scattering only */
#if defined(VERTEX_MERGING_ONLY)
        w = (pathFlags[slot] & PATH_SPECULAR) ? 1.0f : 0.0f; /* merging covers the rest */
#elif defined(BIDIRECTIONAL)
        if (hit_depth(pathDepth, slot) > 1) { /* not the camera ray */
            PathMis mis = load_mis(pathMis, slot);
            float emissionPdfW;
            background_hit_pdfs(lightPdf, scene->radius, &emissionPdfW);
            w = mis_weight_emission_hit(mis, lightPdf, emissionPdfW);
        }
#else
        float prevPdf = pathPrevPdf[slot];
        if (prevPdf > 0.0f)
            w = prevPdf * prevPdf / (prevPdf * prevPdf + lightPdf * lightPdf);
#endif
        add_radiance(pixelRadiance, pathPixel[slot], v3_mul(v3_scale(load_vec3(pathThroughput, slot), w), radiance),
                     &rejected);
    }
#endif
    report_nonfinite(queueCounters, rejected);
}
