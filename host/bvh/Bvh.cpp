#include "Bvh.h"

#include "../Error.h"

#include <algorithm>
#include <chrono>
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

struct BuildTriangle {
    Bounds bounds;
    Vec3 centroid;
    uint32_t index;
};

class Builder {
public:
    // Subtrees at depth < parallelDepth are built in parallel: 2^parallelDepth
    // threads at most. The tree is the same for any parallelDepth.
    Builder(std::vector<BuildTriangle>& tris, int parallelDepth) : tris_(tris), parallelDepth_(parallelDepth) {}

    void build(Bvh& bvh)
    {
        nodes_ = &bvh.nodes;
        node(0, uint32_t(tris_.size()), 0);
        bvh.depth = maxDepth_;
    }

private:
    // Appends the subtree for tris_[begin, end) depth-first; returns its index.
    int node(uint32_t begin, uint32_t end, int depth)
    {
        maxDepth_ = std::max(maxDepth_, depth);
        Bounds bounds, centroids;
        for (uint32_t i = begin; i < end; ++i) {
            bounds.extend(tris_[i].bounds);
            centroids.extend(tris_[i].centroid);
        }
        int index = int(nodes_->size());
        nodes_->push_back(BvhNode{});
        uint32_t count = end - begin;

        uint32_t mid = count > 1 ? split(begin, end, bounds, centroids, depth) : begin;
        BvhNode n{};
        for (int a = 0; a < 3; ++a) { n.lo[a] = bounds.lo[a]; n.hi[a] = bounds.hi[a]; }
        if (mid == begin) { // leaf
            n.offset = int(begin);
            n.primCount = uint16_t(count);
        } else if (depth < parallelDepth_ && count >= kParallelMinTriangles) {
            // The two subtrees (disjoint ranges of tris_) on two threads, each
            // into a node list of its own, then appended in depth-first order.
            n.axis = uint16_t(splitAxis_);
            std::vector<BvhNode> left, right;
            Builder leftBuilder(tris_, parallelDepth_), rightBuilder(tris_, parallelDepth_);
            leftBuilder.nodes_ = &left;
            rightBuilder.nodes_ = &right;
            std::future<void> done =
                std::async(std::launch::async, [&] { leftBuilder.node(begin, mid, depth + 1); });
            rightBuilder.node(mid, end, depth + 1);
            done.get();
            maxDepth_ = std::max({maxDepth_, leftBuilder.maxDepth_, rightBuilder.maxDepth_});
            append(left);
            n.offset = append(right);
        } else {
            n.axis = uint16_t(splitAxis_);
            node(begin, mid, depth + 1);
            n.offset = node(mid, end, depth + 1);
        }
        (*nodes_)[index] = n;
        return index;
    }

    // Appends a subtree built with indices from 0, moving its interior nodes'
    // second-child indices by where it lands; returns the index of its root.
    int append(const std::vector<BvhNode>& subtree)
    {
        int base = int(nodes_->size());
        for (BvhNode n : subtree) {
            if (n.primCount == 0) n.offset += base;
            nodes_->push_back(n);
        }
        return base;
    }

    // Partitions [begin, end) and returns the split point, or begin for a leaf.
    uint32_t split(uint32_t begin, uint32_t end, const Bounds& bounds, const Bounds& centroids, int depth)
    {
        uint32_t count = end - begin;
        int axis = centroids.largestAxis();
        splitAxis_ = axis;
        if (centroids.extent()[axis] <= 0.0f || depth >= kMedianSplitDepth) {
            // All centroids coincide (or the tree is deep already).
            return count <= kMaxLeafSize ? begin : medianSplit(begin, end, axis);
        }

        // Binned SAH (Wald 2007) on all three axes: cost of a split =
        // traversal + Σ_side area(side)/area(node) · count(side).
        float bestCost = INFINITY;
        int bestAxis = -1, bestBin = -1;
        for (int a = 0; a < 3; ++a) {
            float extent = centroids.extent()[a];
            if (extent <= 0.0f) continue;
            Bounds binBounds[kBins];
            uint32_t binCount[kBins] = {};
            float scale = kBins / extent;
            for (uint32_t i = begin; i < end; ++i) {
                int b = std::min(kBins - 1, int((tris_[i].centroid[a] - centroids.lo[a]) * scale));
                binBounds[b].extend(tris_[i].bounds);
                binCount[b]++;
            }
            float rightArea[kBins];
            uint32_t rightCount[kBins];
            Bounds acc;
            uint32_t n = 0;
            for (int b = kBins - 1; b > 0; --b) {
                acc.extend(binBounds[b]);
                n += binCount[b];
                rightArea[b] = acc.surfaceArea();
                rightCount[b] = n;
            }
            acc = Bounds();
            n = 0;
            for (int b = 0; b < kBins - 1; ++b) {
                acc.extend(binBounds[b]);
                n += binCount[b];
                if (n == 0 || rightCount[b + 1] == 0) continue;
                float cost = acc.surfaceArea() * n + rightArea[b + 1] * rightCount[b + 1];
                if (cost < bestCost) { bestCost = cost; bestAxis = a; bestBin = b; }
            }
        }
        float area = bounds.surfaceArea();
        float splitCost = area > 0 ? kTraversalCost + bestCost / area : INFINITY;
        if (count <= kMaxLeafSize && splitCost >= float(count)) return begin;
        if (bestAxis < 0) return medianSplit(begin, end, axis);

        splitAxis_ = bestAxis;
        float lo = centroids.lo[bestAxis], scale = kBins / centroids.extent()[bestAxis];
        auto it = std::partition(tris_.begin() + begin, tris_.begin() + end, [&](const BuildTriangle& t) {
            return std::min(kBins - 1, int((t.centroid[bestAxis] - lo) * scale)) <= bestBin;
        });
        return uint32_t(it - tris_.begin());
    }

    // Halves [begin, end) at the median centroid along `axis`.
    uint32_t medianSplit(uint32_t begin, uint32_t end, int axis)
    {
        uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(tris_.begin() + begin, tris_.begin() + mid, tris_.begin() + end,
                         [axis](const BuildTriangle& a, const BuildTriangle& b) {
                             return a.centroid[axis] < b.centroid[axis];
                         });
        return mid;
    }

    std::vector<BuildTriangle>& tris_;
    std::vector<BvhNode>* nodes_ = nullptr;
    int parallelDepth_ = 0;
    int maxDepth_ = 0;
    int splitAxis_ = 0;
};

} // namespace

Bvh buildBvh(const std::vector<Vec3>& vertices)
{
    auto start = std::chrono::steady_clock::now();
    size_t count = vertices.size() / 3;
    if (count == 0) throw Error("cannot build a BVH over no triangles");
    if (count > size_t(INT32_MAX) / 3) throw Error("too many triangles for 32-bit indices");
    std::vector<BuildTriangle> tris(count);
    for (size_t t = 0; t < count; ++t) {
        for (int k = 0; k < 3; ++k) tris[t].bounds.extend(vertices[3 * t + k]);
        tris[t].centroid = tris[t].bounds.center();
        tris[t].index = uint32_t(t);
    }
    Bvh bvh;
    bvh.nodes.reserve(2 * count);
    // Two levels more than the cores need: splits near the root are often
    // uneven, and more, smaller subtrees balance the cores.
    int parallelDepth = 2;
    for (unsigned threads = std::max(1u, std::thread::hardware_concurrency()); (1u << (parallelDepth - 2)) < threads;)
        ++parallelDepth;
    Builder(tris, parallelDepth).build(bvh);
    bvh.triangleOrder.resize(count);
    for (size_t i = 0; i < count; ++i) bvh.triangleOrder[i] = tris[i].index;
    bvh.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

} // namespace wv
