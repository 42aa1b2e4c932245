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

// A node of the binary SAH tree, depth-first: an interior node's first child
// is the next node, its second at secondChild. Every node covers the
// triangles tris_[begin, begin + count).
struct BinaryNode {
    Bounds bounds;
    uint32_t begin = 0, count = 0;
    int secondChild = -1; // -1 for a leaf
    bool leaf() const { return secondChild < 0; }
};

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

    void build(std::vector<BinaryNode>& nodes)
    {
        nodes_ = &nodes;
        node(0, uint32_t(tris_.size()), 0);
    }

private:
    // Appends the subtree for tris_[begin, end) depth-first; returns its index.
    int node(uint32_t begin, uint32_t end, int depth)
    {
        Bounds bounds, centroids;
        for (uint32_t i = begin; i < end; ++i) {
            bounds.extend(tris_[i].bounds);
            centroids.extend(tris_[i].centroid);
        }
        int index = int(nodes_->size());
        nodes_->push_back(BinaryNode{});
        uint32_t count = end - begin;

        uint32_t mid = count > 1 ? split(begin, end, bounds, centroids, depth) : begin;
        BinaryNode n;
        n.bounds = bounds;
        n.begin = begin;
        n.count = count;
        if (mid == begin) { // leaf
        } else if (depth < parallelDepth_ && count >= kParallelMinTriangles) {
            // The two subtrees (disjoint ranges of tris_) on two threads, each
            // into a node list of its own, then appended in depth-first order.
            std::vector<BinaryNode> left, right;
            Builder leftBuilder(tris_, parallelDepth_), rightBuilder(tris_, parallelDepth_);
            leftBuilder.nodes_ = &left;
            rightBuilder.nodes_ = &right;
            std::future<void> done =
                std::async(std::launch::async, [&] { leftBuilder.node(begin, mid, depth + 1); });
            rightBuilder.node(mid, end, depth + 1);
            done.get();
            append(left);
            n.secondChild = append(right);
        } else {
            node(begin, mid, depth + 1);
            n.secondChild = node(mid, end, depth + 1);
        }
        (*nodes_)[index] = n;
        return index;
    }

    // Appends a subtree built with indices from 0, moving its interior nodes'
    // second-child indices by where it lands; returns the index of its root.
    int append(const std::vector<BinaryNode>& subtree)
    {
        int base = int(nodes_->size());
        for (BinaryNode n : subtree) {
            if (!n.leaf()) n.secondChild += base;
            nodes_->push_back(n);
        }
        return base;
    }

    // Partitions [begin, end) and returns the split point, or begin for a leaf.
    uint32_t split(uint32_t begin, uint32_t end, const Bounds& bounds, const Bounds& centroids, int depth)
    {
        uint32_t count = end - begin;
        int axis = centroids.largestAxis();
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
    std::vector<BinaryNode>* nodes_ = nullptr;
    int parallelDepth_ = 0;
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
    Collapser(const std::vector<BinaryNode>& binary, const std::vector<Vec3>& vertices, Bvh& bvh)
        : binary_(binary), vertices_(vertices), bvh_(bvh), height_(binary.size(), 0)
    {
        for (size_t i = binary.size(); i-- > 0;)
            if (!binary[i].leaf()) height_[i] = 1 + std::max(height_[i + 1], height_[binary[i].secondChild]);
    }

    void collapse()
    {
        if (height_[0] > kBvhStackSize - 1) throw Error("internal error: the binary BVH is too deep");
        bvh_.nodes.emplace_back();
        fill(0, 0, kBvhStackSize - 1, 1);
    }

private:
    bool isLeaf(int b) const { return binary_[b].leaf() || binary_[b].count <= TRIANGLE_PACKET_WIDTH; }
    int height(int b) const { return isLeaf(b) ? 0 : height_[b]; }

    // Wide node `index` from binary node b, whose stack budget is `budget`.
    void fill(int index, int b, int budget, int depth)
    {
        bvh_.depth = std::max(bvh_.depth, depth);
        int children[BVH_WIDTH];
        int k = 0;
        if (isLeaf(b)) children[k++] = b; // the root of a tiny scene
        else { children[k++] = b + 1; children[k++] = binary_[b].secondChild; }
        while (k < BVH_WIDTH) {
            int best = -1;
            float bestArea = -1;
            for (int i = 0; i < k; ++i) {
                int c = children[i];
                if (isLeaf(c)) continue;
                int tallest = std::max(height(c + 1), height(binary_[c].secondChild));
                for (int j = 0; j < k; ++j)
                    if (j != i) tallest = std::max(tallest, height(children[j]));
                if (k + tallest > budget) continue; // (k + 1 children) - 1 pushes
                float area = binary_[c].bounds.surfaceArea();
                if (area > bestArea) { bestArea = area; best = i; }
            }
            if (best < 0) break;
            int c = children[best];
            children[best] = c + 1;
            children[k++] = binary_[c].secondChild;
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
            const BinaryNode& c = binary_[children[i]];
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
        std::vector<TrianglePacket> leafPackets = packTriangles(vertices_, bvh_.triangleOrder, begin, count);
        bvh_.packets.insert(bvh_.packets.end(), leafPackets.begin(), leafPackets.end());
        return ~(first * 8 + packets - 1);
    }

    const std::vector<BinaryNode>& binary_;
    const std::vector<Vec3>& vertices_;
    Bvh& bvh_;
    std::vector<int> height_;
};

// Σ over nodes of area(node)/area(root) · (traversal cost, or triangles for a leaf).
double sahCost(const std::vector<BinaryNode>& nodes)
{
    double rootArea = nodes[0].bounds.surfaceArea(), cost = 0;
    if (!(rootArea > 0)) return 0;
    for (const BinaryNode& n : nodes)
        cost += n.bounds.surfaceArea() / rootArea * (n.leaf() ? double(n.count) : double(kTraversalCost));
    return cost;
}

} // namespace

std::vector<TrianglePacket> packTriangles(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& order,
                                          uint32_t begin, uint32_t count)
{
    std::vector<TrianglePacket> packets((count + TRIANGLE_PACKET_WIDTH - 1) / TRIANGLE_PACKET_WIDTH);
    for (size_t p = 0; p < packets.size(); ++p)
        for (uint32_t lane = 0; lane < TRIANGLE_PACKET_WIDTH; ++lane) {
            uint32_t slot = uint32_t(p * TRIANGLE_PACKET_WIDTH + lane);
            bool real = slot < count;
            // Padding repeats the packet's first triangle, so no lane is degenerate.
            uint32_t position = begin + (real ? slot : uint32_t(p * TRIANGLE_PACKET_WIDTH));
            packets[p].triangle[lane] = real ? int(position) : -1;
            for (int v = 0; v < 3; ++v)
                for (int a = 0; a < 3; ++a) packets[p].v[v][a][lane] = vertices[3 * order[position] + v][a];
        }
    return packets;
}

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
    std::vector<BinaryNode> binary;
    binary.reserve(2 * count);
    // Two levels more than the cores need: splits near the root are often
    // uneven, and more, smaller subtrees balance the cores.
    int parallelDepth = 2;
    for (unsigned threads = std::max(1u, std::thread::hardware_concurrency()); (1u << (parallelDepth - 2)) < threads;)
        ++parallelDepth;
    Builder(tris, parallelDepth).build(binary);
    Bvh bvh;
    bvh.binaryNodes = binary.size();
    bvh.sahCost = sahCost(binary);
    bvh.triangleOrder.resize(count);
    for (size_t i = 0; i < count; ++i) bvh.triangleOrder[i] = tris[i].index;
    Collapser(binary, vertices, bvh).collapse();
    bvh.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

} // namespace wv
