// MikkTSpace, written from the algorithm's description (Mikkelsen 2008 and
// the reference implementation's documentation), for triangles only:
//  1. corners with equal position, normal and UV are one vertex (welded);
//     triangles with two corners on one vertex are degenerate and take their
//     frames from other triangles at the end;
//  2. each triangle gets unit ∂p/∂s and ∂p/∂t from its UVs, and whether its
//     UV mapping preserves orientation;
//  3. around each vertex, the triangles reachable from one another across
//     the edges at that vertex, with the same orientation, form a group (a
//     mirror seam or a UV island's border splits the triangles around a
//     vertex into several);
//  4. a corner's tangent is the sum over its group of each triangle's ∂p/∂s
//     projected into the plane of the vertex normal and normalized, weighted
//     by the triangle's angle at the vertex measured in that plane.
// MikkTSpace's angular threshold is 180 degrees by default, so a group's
// "subgroups" hold all of its triangles but those whose ∂p/∂s or ∂p/∂t point
// exactly opposite; that rule is kept (but for groups of more than 64
// triangles). The handedness is the group's orientation. UVs enter as
// (u, −v): glTF's v runs down the image, and MikkTSpace's bitangent points
// along its second coordinate, which then is "up" as glTF's normal textures
// want.
#include "Tangents.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <numeric>
#include <tuple>
#include <utility>

namespace wv {
namespace {

bool notZero(float x) { return std::fabs(x) > FLT_MIN; }
bool notZero(Vec3 a) { return notZero(a.x) || notZero(a.y) || notZero(a.z); }
Vec3 normalizedIfNotZero(Vec3 a) { return notZero(a) ? normalize(a) : a; }
// a less its component along the unit vector n.
Vec3 inPlane(Vec3 a, Vec3 n) { return a - n * dot(n, a); }

// A welded vertex.
struct Vertex {
    Vec3 p, n;
    float s, t; // (u, −v)
};

struct Triangle {
    Vec3 alongS, alongT;       // unit ∂p/∂s and ∂p/∂t; zero where undefined
    bool orientationPreserving = false;
    bool groupWithAny = true;  // no usable UV mapping: joins any group, adds nothing
    bool degenerate = false;   // two corners are one vertex
    int neighbour[3] = {-1, -1, -1}; // across the edge from corner k to corner k + 1
    int group[3] = {-1, -1, -1};     // of corner k
};

struct Group {
    uint32_t vertex;
    bool orientationPreserving;
    std::vector<int> triangles;
};

// Groups of more triangles than this (a vertex at the centre of a large
// fan) skip the pairwise subgroup test, which costs the square of their size,
// and sum all their triangles: the test only ever leaves out a triangle
// whose ∂p/∂s or ∂p/∂t points exactly opposite another's.
const size_t kLargeGroup = 64;

// Some unit vector perpendicular to n (any, where n is zero).
Vec3 anyPerpendicular(Vec3 n)
{
    Vec3 t = cross(std::fabs(n.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0), n);
    return length(t) > 0.0f ? normalize(t) : Vec3(1, 0, 0);
}

class MikkTSpace {
public:
    MikkTSpace(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals, const std::vector<float>& uvs,
               const std::vector<uint32_t>& indices)
        : triangles_(indices.size() / 3)
    {
        weld(positions, normals, uvs, indices);
        describeTriangles();
        findNeighbours();
        formGroups();
    }

    std::vector<float> tangents()
    {
        size_t corners = 3 * triangles_.size();
        std::vector<Vec3> tangent(corners, Vec3(0, 0, 0));
        std::vector<float> sign(corners, 1.0f);
        for (const Group& g : groups_) evaluate(g, tangent, sign);
        // Degenerate triangles take the frame of the first good corner on the same vertex.
        std::vector<int> firstGoodCorner(vertices_.size(), -1);
        for (size_t c = 0; c < corners; ++c)
            if (!triangles_[c / 3].degenerate && firstGoodCorner[corner_[c]] < 0) firstGoodCorner[corner_[c]] = int(c);
        for (size_t c = 0; c < corners; ++c) {
            int good = firstGoodCorner[corner_[c]];
            if (triangles_[c / 3].degenerate && good >= 0) {
                tangent[c] = tangent[size_t(good)];
                sign[c] = sign[size_t(good)];
            }
        }
        std::vector<float> out(4 * corners);
        for (size_t c = 0; c < corners; ++c) {
            Vec3 t = tangent[c];
            if (!notZero(t) || !isFinite(t)) t = anyPerpendicular(vertices_[corner_[c]].n);
            out[4 * c] = t.x;
            out[4 * c + 1] = t.y;
            out[4 * c + 2] = t.z;
            out[4 * c + 3] = sign[c];
        }
        return out;
    }

private:
    // Step 1. Without normals every corner has its triangle's (glTF's flat
    // shading), so corners of different triangles never weld.
    void weld(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals, const std::vector<float>& uvs,
              const std::vector<uint32_t>& indices)
    {
        size_t corners = 3 * triangles_.size();
        bool flat = normals.size() != positions.size();
        std::vector<Vertex> source(flat ? corners : positions.size());
        std::vector<uint32_t> sourceOf(corners);
        auto uv = [&](uint32_t v, Vertex& out) {
            out.s = uvs.size() >= 2 * size_t(v) + 2 ? uvs[2 * size_t(v)] : 0.0f;
            out.t = uvs.size() >= 2 * size_t(v) + 2 ? -uvs[2 * size_t(v) + 1] : 0.0f;
        };
        if (flat) {
            for (size_t c = 0; c < corners; ++c) {
                size_t first = c - c % 3;
                Vec3 n = cross(positions[indices[first + 1]] - positions[indices[first]],
                               positions[indices[first + 2]] - positions[indices[first]]);
                source[c].p = positions[indices[c]];
                source[c].n = normalizedIfNotZero(n);
                uv(indices[c], source[c]);
                sourceOf[c] = uint32_t(c);
            }
        } else {
            for (size_t v = 0; v < positions.size(); ++v) {
                source[v].p = positions[v];
                source[v].n = normalizedIfNotZero(normals[v]);
                uv(uint32_t(v), source[v]);
            }
            std::copy_n(indices.begin(), corners, sourceOf.begin());
        }
        // Equal vertices (bit for bit) become one: sorted by their bits.
        std::vector<std::array<uint32_t, 8>> bits(source.size());
        for (size_t i = 0; i < source.size(); ++i) {
            const Vertex& v = source[i];
            float f[8] = {v.p.x, v.p.y, v.p.z, v.n.x, v.n.y, v.n.z, v.s, v.t};
            std::memcpy(bits[i].data(), f, sizeof f);
        }
        std::vector<uint32_t> order(source.size());
        std::iota(order.begin(), order.end(), 0u);
        std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return bits[a] < bits[b]; });
        std::vector<uint32_t> welded(source.size());
        for (size_t i = 0; i < order.size(); ++i) {
            if (i == 0 || bits[order[i]] != bits[order[i - 1]]) vertices_.push_back(source[order[i]]);
            welded[order[i]] = uint32_t(vertices_.size() - 1);
        }
        corner_.resize(corners);
        for (size_t c = 0; c < corners; ++c) corner_[c] = welded[sourceOf[c]];
    }

    // Step 2. s and t per the reference's eqs. 18-19: e1 = p1 − p0 =
    // Δs1 ∂p/∂s + Δt1 ∂p/∂t, e2 likewise, solved up to the factor 1/area,
    // whose sign says whether the mapping preserves orientation.
    void describeTriangles()
    {
        for (size_t f = 0; f < triangles_.size(); ++f) {
            Triangle& tri = triangles_[f];
            uint32_t a = corner_[3 * f], b = corner_[3 * f + 1], c = corner_[3 * f + 2];
            tri.degenerate = a == b || a == c || b == c;
            if (tri.degenerate) continue;
            const Vertex &v0 = vertices_[a], &v1 = vertices_[b], &v2 = vertices_[c];
            Vec3 e1 = v1.p - v0.p, e2 = v2.p - v0.p;
            float s1 = v1.s - v0.s, t1 = v1.t - v0.t, s2 = v2.s - v0.s, t2 = v2.t - v0.t;
            float signedArea = s1 * t2 - t1 * s2;
            Vec3 alongS = e1 * t2 - e2 * t1, alongT = e1 * (-s2) + e2 * s1;
            tri.orientationPreserving = signedArea > 0.0f;
            if (!notZero(signedArea)) continue;
            float sign = tri.orientationPreserving ? 1.0f : -1.0f;
            float lengthS = length(alongS), lengthT = length(alongT);
            if (notZero(lengthS)) tri.alongS = alongS * (sign / lengthS);
            if (notZero(lengthT)) tri.alongT = alongT * (sign / lengthT);
            float area = std::fabs(signedArea);
            if (notZero(lengthS / area) && notZero(lengthT / area)) tri.groupWithAny = false;
        }
    }

    // Edges meet the reversed edge of another triangle; where several could
    // (a non-manifold edge), edges pair in triangle order.
    void findNeighbours()
    {
        struct Edge {
            uint32_t lo, hi;
            int triangle, k;
        };
        std::vector<Edge> edges;
        for (size_t f = 0; f < triangles_.size(); ++f) {
            if (triangles_[f].degenerate) continue;
            for (int k = 0; k < 3; ++k) {
                uint32_t a = corner_[3 * f + size_t(k)], b = corner_[3 * f + size_t(k + 1) % 3];
                edges.push_back({std::min(a, b), std::max(a, b), int(f), k});
            }
        }
        std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
            return std::tie(x.lo, x.hi, x.triangle, x.k) < std::tie(y.lo, y.hi, y.triangle, y.k);
        });
        auto from = [&](const Edge& e) { return corner_[3 * size_t(e.triangle) + size_t(e.k)]; };
        for (size_t i = 0; i < edges.size(); ++i) {
            const Edge& e = edges[i];
            if (triangles_[size_t(e.triangle)].neighbour[e.k] >= 0) continue;
            for (size_t j = i + 1; j < edges.size() && edges[j].lo == e.lo && edges[j].hi == e.hi; ++j) {
                const Edge& o = edges[j];
                if (from(o) != from(e) && triangles_[size_t(o.triangle)].neighbour[o.k] < 0) {
                    triangles_[size_t(e.triangle)].neighbour[e.k] = o.triangle;
                    triangles_[size_t(o.triangle)].neighbour[o.k] = e.triangle;
                    break;
                }
            }
        }
    }

    int cornerAt(size_t f, uint32_t vertex) const
    {
        for (int k = 0; k < 3; ++k)
            if (corner_[3 * f + size_t(k)] == vertex) return k;
        return -1;
    }

    // Step 3: each unassigned corner starts a group, which grows depth first
    // across the two edges at its vertex (the reference's recursion, with an
    // explicit stack, left neighbour first).
    void formGroups()
    {
        std::vector<int> stack;
        auto pushNeighbours = [&](size_t f, int k) {
            int left = triangles_[f].neighbour[k], right = triangles_[f].neighbour[(k + 2) % 3];
            if (right >= 0) stack.push_back(right);
            if (left >= 0) stack.push_back(left);
        };
        for (size_t f = 0; f < triangles_.size(); ++f) {
            if (triangles_[f].degenerate) continue;
            for (int k = 0; k < 3; ++k) {
                if (triangles_[f].group[k] >= 0) continue;
                int g = int(groups_.size());
                groups_.push_back({corner_[3 * f + size_t(k)], triangles_[f].orientationPreserving, {int(f)}});
                triangles_[f].group[k] = g;
                pushNeighbours(f, k);
                while (!stack.empty()) {
                    size_t u = size_t(stack.back());
                    stack.pop_back();
                    Triangle& tri = triangles_[u];
                    int at = cornerAt(u, groups_[size_t(g)].vertex);
                    if (at < 0 || tri.group[at] >= 0) continue;
                    // A triangle without a UV mapping takes the orientation of the first group to reach it.
                    if (tri.groupWithAny && tri.group[0] < 0 && tri.group[1] < 0 && tri.group[2] < 0)
                        tri.orientationPreserving = groups_[size_t(g)].orientationPreserving;
                    if (tri.orientationPreserving != groups_[size_t(g)].orientationPreserving) continue;
                    groups_[size_t(g)].triangles.push_back(int(u));
                    tri.group[at] = g;
                    pushNeighbours(u, at);
                }
            }
        }
    }

    // Step 4 for every corner of group g.
    void evaluate(const Group& g, std::vector<Vec3>& tangent, std::vector<float>& sign) const
    {
        float handedness = g.orientationPreserving ? 1.0f : -1.0f;
        size_t m = g.triangles.size();
        if (m > kLargeGroup) { // one subgroup: see kLargeGroup
            Vec3 shared = tangentOf(g.triangles, g.vertex);
            for (int f : g.triangles) {
                size_t c = 3 * size_t(f) + size_t(cornerAt(size_t(f), g.vertex));
                tangent[c] = shared;
                sign[c] = handedness;
            }
            return;
        }
        const float threshold = float(std::cos(double(float(M_PI)))); // 180 degrees, as the reference computes it
        Vec3 n = vertices_[g.vertex].n;
        std::vector<Vec3> s(m), t(m);
        for (size_t i = 0; i < m; ++i) {
            const Triangle& tri = triangles_[size_t(g.triangles[i])];
            s[i] = normalizedIfNotZero(inPlane(tri.alongS, n));
            t[i] = normalizedIfNotZero(inPlane(tri.alongT, n));
        }
        std::vector<std::pair<std::vector<int>, Vec3>> subgroups;
        for (size_t i = 0; i < m; ++i) {
            int f = g.triangles[i];
            std::vector<int> members;
            for (size_t j = 0; j < m; ++j) {
                int o = g.triangles[j];
                bool any = triangles_[size_t(f)].groupWithAny || triangles_[size_t(o)].groupWithAny;
                if (any || o == f || (dot(s[i], s[j]) > threshold && dot(t[i], t[j]) > threshold))
                    members.push_back(o);
            }
            std::sort(members.begin(), members.end());
            auto found = std::find_if(subgroups.begin(), subgroups.end(),
                                      [&](const auto& sg) { return sg.first == members; });
            if (found == subgroups.end()) {
                subgroups.emplace_back(members, tangentOf(members, g.vertex));
                found = subgroups.end() - 1;
            }
            size_t c = 3 * size_t(f) + size_t(cornerAt(size_t(f), g.vertex));
            tangent[c] = found->second;
            sign[c] = handedness;
        }
    }

    // The members' ∂p/∂s in the normal's plane, weighted by their angles at
    // the vertex in that plane.
    Vec3 tangentOf(const std::vector<int>& members, uint32_t vertex) const
    {
        Vec3 n = vertices_[vertex].n, sum(0, 0, 0);
        for (int f : members) {
            const Triangle& tri = triangles_[size_t(f)];
            if (tri.groupWithAny) continue;
            int k = cornerAt(size_t(f), vertex);
            Vec3 p = vertices_[vertex].p;
            Vec3 previous = vertices_[corner_[3 * size_t(f) + size_t(k + 2) % 3]].p;
            Vec3 next = vertices_[corner_[3 * size_t(f) + size_t(k + 1) % 3]].p;
            Vec3 a = normalizedIfNotZero(inPlane(previous - p, n)), b = normalizedIfNotZero(inPlane(next - p, n));
            float angle = float(std::acos(double(std::max(-1.0f, std::min(1.0f, dot(a, b))))));
            sum = sum + normalizedIfNotZero(inPlane(tri.alongS, n)) * angle;
        }
        return normalizedIfNotZero(sum);
    }

    std::vector<Triangle> triangles_;
    std::vector<Vertex> vertices_;
    std::vector<uint32_t> corner_; // welded vertex of each corner
    std::vector<Group> groups_;
};

} // namespace

std::vector<float> mikkTSpaceTangents(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                                      const std::vector<float>& uvs, const std::vector<uint32_t>& indices)
{
    return MikkTSpace(positions, normals, uvs, indices).tangents();
}

} // namespace wv
