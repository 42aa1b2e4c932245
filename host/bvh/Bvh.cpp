#include "Bvh.h"

#include "../Error.h"

#include <algorithm>
#include <chrono>
#include <list>
#include <mutex>
#include <future>
#include <thread>

namespace wv {
namespace {

constexpr int kBins = 16;
constexpr int kMaxLeafSize = 8;
constexpr float kTraversalCost = 1.0f;   // relative to one triangle test
// Past this depth splits are object medians, which halve the count and so
// finish within log2(n) <= 31 more levels: depth stays within kMaxBvhDepth.
constexpr int kMedianSplitDepth = 32;
// Below a split of at least this many triangles, near the root, the two
// subtrees are built on two threads.
constexpr uint32_t kParallelMinTriangles = 16384;

// A node of the binary SAH tree, covering the triangles tris[begin, begin +
// count); height is 0 for a leaf. Children are pointers: a subtree built on a
// thread of its own lives in an array of its own, and nothing is copied.
struct BinaryNode {
    Bounds bounds;
    uint32_t begin, count;
    const BinaryNode* first;  // null for a leaf
    const BinaryNode* second;
    int height;
    bool leaf() const { return first == nullptr; }
};

// Four floats in one SIMD register (GCC/Clang vector extension: SSE, NEON).
typedef float V4 __attribute__((vector_size(16)));
typedef int32_t I4 __attribute__((vector_size(16)));
inline V4 vmin(V4 a, V4 b) { return a < b ? a : b; }
inline V4 vmax(V4 a, V4 b) { return a > b ? a : b; }

// A box with lanes x, y, z (lane 3 unused).
struct Box4 {
    V4 lo = {INFINITY, INFINITY, INFINITY, INFINITY};
    V4 hi = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
    void extend(V4 l, V4 h) { lo = vmin(lo, l); hi = vmax(hi, h); }
    void extend(const Box4& b) { extend(b.lo, b.hi); }
    // Bounds::surfaceArea, operation by operation.
    float surfaceArea() const
    {
        if (lo[0] > hi[0]) return 0.0f;
        V4 e = hi - lo;
        return 2.0f * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
    }
    Bounds bounds() const
    {
        Bounds b;
        b.lo = Vec3(lo[0], lo[1], lo[2]);
        b.hi = Vec3(hi[0], hi[1], hi[2]);
        return b;
    }
};

// 32 bytes: the triangle's box, and its scene index in the high box's lane 3.
struct BuildTriangle {
    V4 lo, hiAndIndex;
    V4 hi() const { return V4(I4(hiAndIndex) & I4{-1, -1, -1, 0}); }
    V4 centroid() const { return (lo + hi()) * 0.5f; } // Bounds::center, lane by lane
    uint32_t index() const { return uint32_t(I4(hiAndIndex)[3]); }
};

// Triangles' bounds and centroid bounds.
struct Extent {
    Box4 bounds, centroids;
};

// Node arrays, each reserved up front for the subtree it holds (2m - 1 nodes
// for m triangles), so that pointers into them stay valid; only the pages
// that nodes are written to are ever touched.
class NodeArrays {
public:
    std::vector<BinaryNode>& add(size_t triangles)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        arrays_.emplace_back().reserve(2 * triangles - 1);
        return arrays_.back();
    }

private:
    std::mutex mutex_;
    std::list<std::vector<BinaryNode>> arrays_;
};

class Builder {
public:
    // Subtrees at depth < parallelDepth are built in parallel: 2^parallelDepth
    // threads at most. The tree is the same for any parallelDepth.
    Builder(std::vector<BuildTriangle>& tris, NodeArrays& arrays, int parallelDepth)
        : tris_(tris), arrays_(arrays), parallelDepth_(parallelDepth)
    {
    }

    // Builds the subtree of tris_[begin, end), whose extent is `extent`, into
    // `out` (which has room for it); returns its root.
    const BinaryNode* node(std::vector<BinaryNode>& out, uint32_t begin, uint32_t end, const Extent& extent, int depth)
    {
        BinaryNode& n = out.emplace_back();
        n.bounds = extent.bounds.bounds();
        n.begin = begin;
        n.count = end - begin;
        n.first = n.second = nullptr;
        n.height = 0;
        Extent left, right;
        uint32_t mid = n.count > 1 ? split(begin, end, extent, depth, &left, &right) : begin;
        if (mid == begin) return &n; // leaf

        if (depth < parallelDepth_ && n.count >= kParallelMinTriangles) {
            std::vector<BinaryNode>& leftNodes = arrays_.add(mid - begin);
            std::future<const BinaryNode*> first =
                std::async(std::launch::async, [&] { return node(leftNodes, begin, mid, left, depth + 1); });
            n.second = node(out, mid, end, right, depth + 1);
            n.first = first.get();
        } else {
            n.first = node(out, begin, mid, left, depth + 1);
            n.second = node(out, mid, end, right, depth + 1);
        }
        n.height = 1 + std::max(n.first->height, n.second->height);
        return &n;
    }

private:
    // Partitions [begin, end) and returns the split point with the two sides'
    // extents, or begin for a leaf.
    uint32_t split(uint32_t begin, uint32_t end, const Extent& extent, int depth, Extent* left, Extent* right)
    {
        uint32_t count = end - begin;
        const Bounds centroids = extent.centroids.bounds();
        int axis = centroids.largestAxis();
        if (centroids.extent()[axis] <= 0.0f || depth >= kMedianSplitDepth) {
            // All centroids coincide (or the tree is deep already).
            return count <= kMaxLeafSize ? begin : medianSplit(begin, end, axis, left, right);
        }

        // Binned SAH (Wald 2007) on all three axes in one pass over the
        // triangles: cost of a split = traversal + Σ_side area(side)/area(node) · count(side).
        Box4 bin[3][kBins];
        uint32_t binCount[3][kBins] = {};
        V4 scale = {0, 0, 0, 0};
        for (int a = 0; a < 3; ++a) {
            float e = centroids.extent()[a];
            scale[a] = e > 0.0f ? kBins / e : 0.0f;
        }
        V4 origin = extent.centroids.lo;
        for (uint32_t i = begin; i < end; ++i) {
            const BuildTriangle& t = tris_[i];
            V4 lo = t.lo, hi = t.hi();
            V4 position = ((lo + hi) * 0.5f - origin) * scale;
            for (int a = 0; a < 3; ++a) {
                int b = std::min(kBins - 1, int(position[a]));
                bin[a][b].extend(lo, hi);
                binCount[a][b]++;
            }
        }
        float bestCost = INFINITY;
        int bestAxis = -1, bestBin = -1;
        for (int a = 0; a < 3; ++a) {
            if (scale[a] == 0.0f) continue;
            float rightArea[kBins];
            uint32_t rightCount[kBins];
            Box4 acc;
            uint32_t n = 0;
            for (int b = kBins - 1; b > 0; --b) {
                acc.extend(bin[a][b]);
                n += binCount[a][b];
                rightArea[b] = acc.surfaceArea();
                rightCount[b] = n;
            }
            acc = Box4();
            n = 0;
            for (int b = 0; b < kBins - 1; ++b) {
                acc.extend(bin[a][b]);
                n += binCount[a][b];
                if (n == 0 || rightCount[b + 1] == 0) continue;
                float cost = acc.surfaceArea() * n + rightArea[b + 1] * rightCount[b + 1];
                if (cost < bestCost) { bestCost = cost; bestAxis = a; bestBin = b; }
            }
        }
        float area = extent.bounds.surfaceArea();
        float splitCost = area > 0 ? kTraversalCost + bestCost / area : INFINITY;
        if (count <= kMaxLeafSize && splitCost >= float(count)) return begin;
        if (bestAxis < 0) return medianSplit(begin, end, axis, left, right);

        for (int b = 0; b < kBins; ++b) (b <= bestBin ? left : right)->bounds.extend(bin[bestAxis][b]);
        // Partition in place (two cursors, each triangle looked at once),
        // gathering each side's centroid bounds on the way.
        float lo = origin[bestAxis], s = scale[bestAxis];
        auto goesLeft = [&](V4 c) { return std::min(kBins - 1, int((c[bestAxis] - lo) * s)) <= bestBin; };
        uint32_t i = begin, j = end;
        for (;;) {
            for (V4 c; i < j && goesLeft(c = tris_[i].centroid()); ++i) left->centroids.extend(c, c);
            for (V4 c; i < j && !goesLeft(c = tris_[j - 1].centroid()); --j) right->centroids.extend(c, c);
            if (i >= j) break;
            std::swap(tris_[i], tris_[j - 1]);
        }
        return i;
    }

    // Halves [begin, end) at the median centroid along `axis`.
    uint32_t medianSplit(uint32_t begin, uint32_t end, int axis, Extent* left, Extent* right)
    {
        uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(tris_.begin() + begin, tris_.begin() + mid, tris_.begin() + end,
                         [axis](const BuildTriangle& a, const BuildTriangle& b) {
                             return a.centroid()[axis] < b.centroid()[axis];
                         });
        for (uint32_t i = begin; i < end; ++i) {
            Extent* side = i < mid ? left : right;
            V4 c = tris_[i].centroid();
            side->bounds.extend(tris_[i].lo, tris_[i].hi());
            side->centroids.extend(c, c);
        }
        return mid;
    }

    std::vector<BuildTriangle>& tris_;
    NodeArrays& arrays_;
    int parallelDepth_;
};

// The wide tree from the binary one: each wide node takes a binary node's two
// children, then repeatedly replaces its largest-area interior child by that
// child's two children, until it has BVH_WIDTH (Wald, Benthin, Boulos,
// "Getting Rid of Packets", RT 2008, §3). A subtree of at most
// TRIANGLE_PACKET_WIDTH triangles becomes one leaf packet.
//
// Stack bound: a visit pushes at most (children - 1) entries more than it pops,
// so a traversal from a node never holds more than S(node) = (children - 1) +
// max over interior children of S(child), plus one while pushing. A binary
// subtree of height h can always be collapsed with S <= h (two children per
// node), so each node is given a budget, starting at BVH_STACK_SIZE - 1 >= the
// binary tree's height, and an expansion is taken only if (children - 1) plus
// the largest remaining binary height stays within it.
class Collapser {
public:
    Collapser(const std::vector<Vec3>& vertices, Bvh& bvh) : vertices_(vertices), bvh_(bvh) {}

    void collapse(const BinaryNode* root)
    {
        if (root->height > kMaxBvhDepth) throw Error("internal error: the binary BVH is too deep");
        bvh_.nodes.emplace_back();
        fill(0, root, BVH_STACK_SIZE - 1, 1);
    }

private:
    static bool isLeaf(const BinaryNode* b) { return b->leaf() || b->count <= TRIANGLE_PACKET_WIDTH; }
    static int height(const BinaryNode* b) { return isLeaf(b) ? 0 : b->height; }

    // Wide node `index` from binary node b, whose stack budget is `budget`.
    void fill(int index, const BinaryNode* b, int budget, int depth)
    {
        bvh_.depth = std::max(bvh_.depth, depth);
        const BinaryNode* children[BVH_WIDTH];
        int k = 0;
        if (isLeaf(b)) children[k++] = b; // the root of a tiny scene
        else { children[k++] = b->first; children[k++] = b->second; }
        while (k < BVH_WIDTH) {
            int best = -1;
            float bestArea = -1;
            for (int i = 0; i < k; ++i) {
                const BinaryNode* c = children[i];
                if (isLeaf(c)) continue;
                int tallest = std::max(height(c->first), height(c->second));
                for (int j = 0; j < k; ++j)
                    if (j != i) tallest = std::max(tallest, height(children[j]));
                if (k + tallest > budget) continue; // (k + 1 children) - 1 pushes
                float area = c->bounds.surfaceArea();
                if (area > bestArea) { bestArea = area; best = i; }
            }
            if (best < 0) break;
            const BinaryNode* c = children[best];
            children[best] = c->first;
            children[k++] = c->second;
        }

        BvhNode node;
        for (int i = 0; i < BVH_WIDTH; ++i) {
            for (int a = 0; a < 3; ++a) {
                node.bounds[a][i] = INFINITY;
                node.bounds[3 + a][i] = -INFINITY;
            }
            node.child[i] = 0;
        }
        for (int i = 0; i < k; ++i) {
            const BinaryNode& c = *children[i];
            for (int a = 0; a < 3; ++a) {
                node.bounds[a][i] = c.bounds.lo[a];
                node.bounds[3 + a][i] = c.bounds.hi[a];
            }
            if (isLeaf(children[i])) {
                node.child[i] = leaf(c.begin, c.count);
            } else {
                node.child[i] = int(bvh_.nodes.size());
                bvh_.nodes.emplace_back();
                fill(node.child[i], children[i], budget - (k - 1), depth + 1);
            }
        }
        bvh_.nodes[index] = node;
    }

    // Packs triangles [begin, begin + count) into packets; returns the child code.
    int leaf(uint32_t begin, uint32_t count)
    {
        int first = int(bvh_.packets.size());
        int packets = int((count + TRIANGLE_PACKET_WIDTH - 1) / TRIANGLE_PACKET_WIDTH);
        if (packets > BVH_LEAF_MAX_PACKETS) throw Error("internal error: a BVH leaf has too many triangles");
        if (first > (INT32_MAX >> 3)) throw Error("too many triangles for the BVH's leaf encoding");
        appendPackets(vertices_, bvh_.triangleOrder, begin, count, bvh_.packets);
        return ~(first * 8 + packets - 1);
    }

    const std::vector<Vec3>& vertices_;
    Bvh& bvh_;
};

// Σ over the subtree's nodes of area(node) · (traversal cost, or triangles for a leaf).
double sahCost(const BinaryNode* n)
{
    double own = n->bounds.surfaceArea() * (n->leaf() ? double(n->count) : double(kTraversalCost));
    return n->leaf() ? own : own + sahCost(n->first) + sahCost(n->second);
}

} // namespace

void appendPackets(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& order, uint32_t begin,
                   uint32_t count, std::vector<TrianglePacket>& packets)
{
    for (uint32_t p = 0; p * TRIANGLE_PACKET_WIDTH < count; ++p) {
        TrianglePacket& packet = packets.emplace_back();
        for (uint32_t lane = 0; lane < TRIANGLE_PACKET_WIDTH; ++lane) {
            uint32_t slot = p * TRIANGLE_PACKET_WIDTH + lane;
            bool real = slot < count;
            // Padding repeats the packet's first triangle, so no lane is degenerate.
            uint32_t position = begin + (real ? slot : p * TRIANGLE_PACKET_WIDTH);
            packet.triangle[lane] = real ? int(position) : -1;
            for (int v = 0; v < 3; ++v)
                for (int a = 0; a < 3; ++a) packet.v[v][a][lane] = vertices[3 * order[position] + v][a];
        }
    }
}

Bvh buildBvh(const std::vector<Vec3>& vertices)
{
    auto start = std::chrono::steady_clock::now();
    size_t count = vertices.size() / 3;
    if (count == 0) throw Error("cannot build a BVH over no triangles");
    if (count > size_t(INT32_MAX) / 3) throw Error("too many triangles for 32-bit indices");
    std::vector<BuildTriangle> tris(count);
    Extent all;
    for (size_t t = 0; t < count; ++t) {
        Bounds box;
        for (int k = 0; k < 3; ++k) box.extend(vertices[3 * t + k]);
        V4 lo = {box.lo.x, box.lo.y, box.lo.z, 0}, hi = {box.hi.x, box.hi.y, box.hi.z, 0};
        tris[t].lo = lo;
        tris[t].hiAndIndex = V4(I4(hi) | I4{0, 0, 0, int32_t(t)});
        V4 c = tris[t].centroid();
        all.bounds.extend(lo, hi);
        all.centroids.extend(c, c);
    }
    // Two levels more than the cores need: splits near the root are often
    // uneven, and more, smaller subtrees balance the cores.
    int parallelDepth = 2;
    for (unsigned threads = std::max(1u, std::thread::hardware_concurrency()); (1u << (parallelDepth - 2)) < threads;)
        ++parallelDepth;
    NodeArrays arrays;
    const BinaryNode* root = Builder(tris, arrays, parallelDepth).node(arrays.add(count), 0, uint32_t(count), all, 0);
    Bvh bvh;
    double rootArea = root->bounds.surfaceArea();
    bvh.sahCost = rootArea > 0 ? sahCost(root) / rootArea : 0;
    bvh.triangleOrder.resize(count);
    for (size_t i = 0; i < count; ++i) bvh.triangleOrder[i] = tris[i].index();
    bvh.nodes.reserve(count / 8 + 1);
    bvh.packets.reserve(count / 2 + 1);
    Collapser(vertices, bvh).collapse(root);
    bvh.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

} // namespace wv
