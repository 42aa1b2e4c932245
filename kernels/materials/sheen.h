/* The sheen lobe of KHR_materials_sheen (docs/scenes.md): the Charlie
 * distribution of fibres, D(h) = (2 + 1/α) sin(θh)^(1/α) / (2π) with α = r²
 * (Estevez and Kulla 2017), under Smith's height-correlated shadowing for
 * that distribution, Λ(ω) = P(μ)/μ − 1 with P(μ) = ∫ max(0, ω·h) D dωh the
 * projected area of the fibres ω sees:
 *     f = sheenColor · D / (4 (P(μo) μi + P(μi) μo − μo μi)).
 * P and the lobe's directional albedo E (by which the layers beneath are
 * scaled) are tabulated by scripts/make_sheen_albedo.py (sheen_tables.h). */
#ifndef WAVEVCM_SHEEN_H
#define WAVEVCM_SHEEN_H

#include "core/vec3.h"
#include "interface/inline.h"
#include "materials/sheen_tables.h"

/* Below this roughness the fibres' lobe hugs the horizon too tightly for
 * the tables (and for any sampling); the tables' rows start here. */
#define SHEEN_MIN_ROUGHNESS 0.07f

/* Table t at roughness r (clamped as the tables are) and cos θ = mu, bilinear. */
INLINE float sheen_table(__constant const float* t, float r, float mu)
{
    float x = clamp(mu, 0.0f, 1.0f) * (float)(SHEEN_TABLE_SIZE - 1);
    float y = clamp(r, 0.0f, 1.0f) * (float)(SHEEN_TABLE_SIZE - 1);
    int x0 = min((int)x, SHEEN_TABLE_SIZE - 2), y0 = min((int)y, SHEEN_TABLE_SIZE - 2);
    float fx = x - (float)x0, fy = y - (float)y0;
    __constant const float* row = t + y0 * SHEEN_TABLE_SIZE + x0;
    float a = row[0] + fx * (row[1] - row[0]);
    float b = row[SHEEN_TABLE_SIZE] + fx * (row[SHEEN_TABLE_SIZE + 1] - row[SHEEN_TABLE_SIZE]);
    return a + fy * (b - a);
}

/* The directional albedo of a white sheen of roughness r at cos θ = mu. */
INLINE float sheen_albedo(float r, float mu) { return sheen_table(SHEEN_ALBEDO, r, mu); }

/* P(μ) = μ + sin θ · Q(μ): the fibres' projected area seen at cos θ = mu. */
INLINE float sheen_projected_area(float r, float mu)
{
    return mu + sqrt(fmax(0.0f, 1.0f - mu * mu)) * sheen_table(SHEEN_Q, r, mu);
}

/* f / sheenColor for local directions wo, wi above the surface. */
INLINE float sheen_value(float r, vec3 wo, vec3 wi)
{
    float alpha = fmax(r, SHEEN_MIN_ROUGHNESS);
    alpha *= alpha;
    vec3 h = v3_normalize(v3_add(wo, wi));
    float sin2 = fmax(0.0f, 1.0f - h.z * h.z);
    float d = (2.0f + 1.0f / alpha) * pow(sin2, 0.5f / alpha) * (0.5f * INV_PI_F);
    float denom = sheen_projected_area(r, wo.z) * wi.z + sheen_projected_area(r, wi.z) * wo.z - wo.z * wi.z;
    return d / (4.0f * denom);
}

#endif
