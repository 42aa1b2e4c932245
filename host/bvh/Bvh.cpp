#include "Bvh.h"

#include "../Error.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <future>
#include <list>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#ifdef __linux__
#include <sys/mman.h>
#endif

namespace wv {
namespace {

constexpr int kBins = 16;
constexpr int kMaxLeafSize = 8;
// Nodes of at most this many triangles are binary leaves: one packet of the
// narrower width, tested together whatever the tree below them would be.
// Trees of wider packets take nodes of up to their width as leaves
// (planWide), so one binary tree, and one triangle order, serves both.
constexpr uint32_t kBinaryLeafTriangles = 4;
// Nodes of at most this many triangles, most of the tree's, are binned and
// partitioned by binSmall and partitionSmall (32, 64, 128 and 256 measured:
// 64 as fast as any).
constexpr uint32_t kSmallNode = 64;
constexpr float kTraversalCost = 1.0f;   // relative to one triangle test
// Past this depth splits are object medians, which halve the count and so
// finish within log2(n) <= 31 more levels: depth stays within kMaxBvhDepth.
constexpr int kMedianSplitDepth = 32;
// Below a split of at least this many triangles, near the root, the two
// subtrees are built on two threads.
constexpr uint32_t kParallelMinTriangles = 16384;

// Runs work(i) for i in [0, count) on all cores; rethrows the first exception.
template <typename Work>
void parallelFor(size_t count, Work work)
{
    std::atomic<size_t> next{0};
    auto worker = [&] {
        for (size_t i; (i = next++) < count;) work(i);
    };
    std::vector<std::future<void>> workers;
    unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    for (unsigned w = 1; w < std::min<size_t>(threads, count); ++w)
        workers.push_back(std::async(std::launch::async, worker));
    worker();
    for (std::future<void>& w : workers) w.get();
}

// A node of the binary SAH tree, covering the triangles tris[begin, begin +
// count); height is 0 for a leaf. Children are pointers: a subtree built on a
// thread of its own lives in an array of its own, and nothing is copied.
struct BinaryNode {
    Bounds bounds;
    uint32_t begin, count;
    const BinaryNode* first;  // null for a leaf
    const BinaryNode* second;
    int height;
    // The wide tree's plan (planWide below): cost[j - 1], the least expected
    // cost of this subtree as at most j roots of a wide node; split[j - 1],
    // how: 0 as one root, k > 0 as k roots from `first` and j - k from
    // `second`; wideSplit, that split for the subtree's own wide node's
    // BVH_WIDTH children; asLeaf, whether its one root is a leaf.
    float cost[BVH_WIDTH];
    uint8_t split[BVH_WIDTH];
    uint8_t wideSplit;
    bool asLeaf;
    bool leaf() const { return first == nullptr; }
};

// The wide tree's cost model (Ylitie, Karras, Laine, "Efficient Incoherent
// Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017, §3.1), with
// leaves of packets: a ray into a box of area A visits a wide node there at
// cost A · kNodeVisitCost, or tests a leaf's p packets at A · p ·
// kPacketTestCost. The least total over every way of collapsing the binary
// tree is found bottom up, as each binary node is finished (planWide).
// Weighted by time, not instructions: a visit takes ~50 instructions to a
// packet test's ~90, but it waits on its node's lines before the next visit
// can start and mispredicts on which children were hit, where a leaf's
// packets lie one after another and their tests are straight-line code. On
// the Intel AVX-512 machine (wavevcm_bench, incoherent rays, paired against
// Embree), a visit weighted 8 packet tests instead of 1 took the
// 1M-triangle displaced sphere from 56,364 nodes (12.6 MB) to 11,986
// (2.7 MB; the L2 cache holds 2 MB per core) and from 0.73-0.79x Embree's
// rate to 1.00-1.03x (closest hit) and 0.67-0.73x to 0.84-0.89x (any hit),
// the 130K box from 0.84-0.89x to 1.00-1.10x and 0.85x to 0.93-1.00x; small
// scenes, whose trees are in the cache either way, unchanged. Weights 4 and
// 6 gained less on the 1M sphere, 12 and 16 lost some again. (Measured with
// packets of four triangles; with packets of eight, weights 4, 6 and 8 gave
// the same rates within the spread on the Cornell box, the 130K box, the
// caustics scene and the 1M sphere.)
constexpr float kNodeVisitCost = 8.0f;
constexpr float kPacketTestCost = 1.0f;

// A box's surface area in double (where the float one may overflow), times `scale`.
double scaledArea(const Bounds& b, double scale)
{
    if (b.empty()) return 0;
    double x = double(b.hi.x) - b.lo.x, y = double(b.hi.y) - b.lo.y, z = double(b.hi.z) - b.lo.z;
    return 2 * (x * y + y * z + z * x) * scale;
}

// Costs are areas relative to the scene's box (areaScale = 1 / its area), so
// they stay in float's range whatever the scene's scale.
void planWide(BinaryNode& n, double areaScale, uint32_t packetWidth)
{
    float area = float(scaledArea(n.bounds, areaScale));
    uint32_t packets = (n.count + packetWidth - 1) / packetWidth;
    bool leafAllowed = packets <= BVH_LEAF_MAX_PACKETS;
    float leafCost = leafAllowed ? area * float(packets) * kPacketTestCost : INFINITY;
    std::fill(n.split, n.split + BVH_WIDTH, uint8_t(0));
    n.wideSplit = 0;
    if (n.leaf() || n.count <= packetWidth) { // one packet's triangles or fewer
        n.asLeaf = true;
        std::fill(n.cost, n.cost + BVH_WIDTH, leafCost);
        return;
    }
    // apart[j]: the least cost of the two children as at most j roots, k of them from `first`.
    float apart[BVH_WIDTH + 1];
    uint8_t firstRoots[BVH_WIDTH + 1];
    for (int j = 2; j <= BVH_WIDTH; ++j) {
        apart[j] = INFINITY;
        firstRoots[j] = 1;
        for (int k = 1; k < j; ++k) {
            float c = n.first->cost[k - 1] + n.second->cost[j - k - 1];
            if (c < apart[j]) {
                apart[j] = c;
                firstRoots[j] = uint8_t(k);
            }
        }
    }
    float nodeCost = area * kNodeVisitCost + apart[BVH_WIDTH];
    n.wideSplit = firstRoots[BVH_WIDTH];
    n.asLeaf = leafAllowed && leafCost <= nodeCost;
    n.cost[0] = std::min(leafCost, nodeCost);
    for (int j = 2; j <= BVH_WIDTH; ++j) {
        bool split = apart[j] < n.cost[0];
        n.cost[j - 1] = split ? apart[j] : n.cost[0];
        n.split[j - 1] = split ? firstRoots[j] : 0;
    }
}

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
    LargeArray<BinaryNode>& add(size_t triangles)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        arrays_.emplace_back().reserve(2 * triangles - 1);
        return arrays_.back();
    }

private:
    std::mutex mutex_;
    std::list<LargeArray<BinaryNode>> arrays_;
};

// A node's triangles binned by centroid on each axis: per bin the triangles'
// box and count, set only where `occupied` has the bin's bit.
struct Bins {
    V4 lo[3][kBins], hi[3][kBins];
    uint32_t count[3][kBins];
    uint32_t occupied[3];
};

class Builder {
public:
    // Subtrees at depth < parallelDepth are built in parallel: 2^parallelDepth
    // threads at most. The tree is the same for any parallelDepth.
    // sceneBounds: all the triangles' box.
    // packetWidth: of the wide tree that the plans are made for (planWide).
    Builder(LargeArray<BuildTriangle>& tris, NodeArrays& arrays, int parallelDepth, const Bounds& sceneBounds,
            uint32_t packetWidth)
        : tris_(tris), arrays_(arrays), parallelDepth_(parallelDepth), packetWidth_(packetWidth)
    {
        double area = scaledArea(sceneBounds, 1);
        areaScale_ = area > 0 ? 1 / area : 1;
    }

    // Builds the subtree of tris_[begin, end), whose extent is `extent`, into
    // `out` (which has room for it); returns its root.
    const BinaryNode* node(LargeArray<BinaryNode>& out, uint32_t begin, uint32_t end, const Extent& extent, int depth)
    {
        BinaryNode& n = out.emplace_back();
        n.bounds = extent.bounds.bounds();
        n.begin = begin;
        n.count = end - begin;
        n.first = n.second = nullptr;
        n.height = 0;
        Extent left, right;
        uint32_t mid = n.count > kBinaryLeafTriangles ? split(begin, end, extent, depth, &left, &right) : begin;
        if (mid == begin) { // leaf
            planWide(n, areaScale_, packetWidth_);
            return &n;
        }

        if (depth < parallelDepth_ && n.count >= kParallelMinTriangles) {
            LargeArray<BinaryNode>& leftNodes = arrays_.add(mid - begin);
            std::future<const BinaryNode*> first =
                std::async(std::launch::async, [&] { return node(leftNodes, begin, mid, left, depth + 1); });
            n.second = node(out, mid, end, right, depth + 1);
            n.first = first.get();
        } else {
            n.first = node(out, begin, mid, left, depth + 1);
            n.second = node(out, mid, end, right, depth + 1);
        }
        n.height = 1 + std::max(n.first->height, n.second->height);
        planWide(n, areaScale_, packetWidth_);
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
        V4 scale = {0, 0, 0, 0};
        for (int a = 0; a < 3; ++a) {
            float e = centroids.extent()[a];
            scale[a] = e > 0.0f ? kBins / e : 0.0f;
        }
        V4 origin = extent.centroids.lo;
        Bins bins;
        I4 binIndex[kSmallNode]; // a small node's triangles' bins
        bool small = count <= kSmallNode;
        if (small) binSmall(begin, end, origin, scale, bins, binIndex);
        else binLarge(begin, end, origin, scale, bins);
        // The sweep visits occupied bins only: a split beside an empty bin
        // costs the same as the one before it, never strictly less.
        float bestCost = INFINITY;
        int bestAxis = -1, bestBin = -1;
        for (int a = 0; a < 3; ++a) {
            if (scale[a] == 0.0f) continue;
            int occupied[kBins], m = 0;
            for (uint32_t bits = bins.occupied[a]; bits; bits &= bits - 1) occupied[m++] = __builtin_ctz(bits);
            float rightArea[kBins];
            uint32_t rightCount[kBins];
            Box4 acc;
            uint32_t n = 0;
            for (int j = m - 1; j > 0; --j) {
                acc.extend(bins.lo[a][occupied[j]], bins.hi[a][occupied[j]]);
                n += bins.count[a][occupied[j]];
                rightArea[j] = acc.surfaceArea();
                rightCount[j] = n;
            }
            acc = Box4();
            n = 0;
            for (int j = 0; j < m - 1; ++j) {
                acc.extend(bins.lo[a][occupied[j]], bins.hi[a][occupied[j]]);
                n += bins.count[a][occupied[j]];
                float cost = acc.surfaceArea() * n + rightArea[j + 1] * rightCount[j + 1];
                if (cost < bestCost) { bestCost = cost; bestAxis = a; bestBin = occupied[j]; }
            }
        }
        float area = extent.bounds.surfaceArea();
        float splitCost = area > 0 ? kTraversalCost + bestCost / area : INFINITY;
        if (count <= kMaxLeafSize && splitCost >= float(count)) return begin;
        if (bestAxis < 0) return medianSplit(begin, end, axis, left, right);

        for (uint32_t bits = bins.occupied[bestAxis]; bits; bits &= bits - 1) {
            int b = __builtin_ctz(bits);
            (b <= bestBin ? left : right)->bounds.extend(bins.lo[bestAxis][b], bins.hi[bestAxis][b]);
        }
        if (small) return partitionSmall(begin, end, bins, binIndex, bestAxis, bestBin, left, right);
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

    // The bin of a triangle's centroid on each axis.
    static I4 binOf(V4 lo, V4 hi, V4 origin, V4 scale)
    {
        I4 b = __builtin_convertvector(((lo + hi) * 0.5f - origin) * scale, I4);
        return b < kBins - 1 ? b : I4{kBins - 1, kBins - 1, kBins - 1, kBins - 1};
    }

    // Bins of a large node: every bin set up, then one pass over the
    // triangles with two sets of bins, for even and odd triangles, summed
    // after it: neighbouring triangles often fall into the same bins, and with
    // one set each extend waited for the one before it.
    void binLarge(uint32_t begin, uint32_t end, V4 origin, V4 scale, Bins& bins) const
    {
        Box4 bin[3][kBins], bin2[3][kBins];
        uint32_t binCount[3][kBins] = {}, binCount2[3][kBins] = {};
        uint32_t k = begin;
        for (; k + 1 < end; k += 2) {
            const BuildTriangle& t = tris_[k];
            const BuildTriangle& u = tris_[k + 1];
            V4 lo = t.lo, hi = t.hi(), lo2 = u.lo, hi2 = u.hi();
            I4 b = binOf(lo, hi, origin, scale), b2 = binOf(lo2, hi2, origin, scale);
            for (int a = 0; a < 3; ++a) {
                bin[a][b[a]].extend(lo, hi);
                binCount[a][b[a]]++;
                bin2[a][b2[a]].extend(lo2, hi2);
                binCount2[a][b2[a]]++;
            }
        }
        if (k < end) {
            V4 lo = tris_[k].lo, hi = tris_[k].hi();
            I4 b = binOf(lo, hi, origin, scale);
            for (int a = 0; a < 3; ++a) {
                bin[a][b[a]].extend(lo, hi);
                binCount[a][b[a]]++;
            }
        }
        for (int a = 0; a < 3; ++a) {
            bins.occupied[a] = 0;
            for (int b = 0; b < kBins; ++b) {
                bin[a][b].extend(bin2[a][b]);
                bins.lo[a][b] = bin[a][b].lo;
                bins.hi[a][b] = bin[a][b].hi;
                bins.count[a][b] = binCount[a][b] + binCount2[a][b];
                bins.occupied[a] |= uint32_t(bins.count[a][b] > 0) << b;
            }
        }
    }

    // Bins of a small node, the same as binLarge's: only the bins its
    // triangles fall into are written, so the cost does not grow with kBins,
    // and without a branch on the data (a branch on whether a bin was written
    // already, taken at random, made it no faster than binLarge). Each
    // triangle's bins go to binIndex for partitionSmall.
    void binSmall(uint32_t begin, uint32_t end, V4 origin, V4 scale, Bins& bins, I4* binIndex) const
    {
        // Two passes without a branch on the data: the bins hit are set
        // empty (a bin hit twice is set twice), then extended.
        const V4 empty = {INFINITY, INFINITY, INFINITY, INFINITY};
        uint32_t occupied[3] = {0, 0, 0};
        for (uint32_t k = begin; k < end; ++k) {
            I4 b = binIndex[k - begin] = binOf(tris_[k].lo, tris_[k].hi(), origin, scale);
            for (int a = 0; a < 3; ++a) {
                bins.lo[a][b[a]] = empty;
                bins.hi[a][b[a]] = -empty;
                bins.count[a][b[a]] = 0;
                occupied[a] |= 1u << b[a];
            }
        }
        for (uint32_t k = begin; k < end; ++k) {
            V4 lo = tris_[k].lo, hi = tris_[k].hi();
            I4 b = binIndex[k - begin];
            for (int a = 0; a < 3; ++a) {
                bins.lo[a][b[a]] = vmin(bins.lo[a][b[a]], lo);
                bins.hi[a][b[a]] = vmax(bins.hi[a][b[a]], hi);
                bins.count[a][b[a]]++;
            }
        }
        for (int a = 0; a < 3; ++a) bins.occupied[a] = occupied[a];
    }

    // The partition of a small node by the bins binSmall found, with each
    // side's centroid bounds: stable, through a copy, without a branch on the
    // side, which deep in the tree is no longer predictable from the
    // triangle before (the two-cursor partition below branches on it).
    uint32_t partitionSmall(uint32_t begin, uint32_t end, const Bins& bins, const I4* binIndex, int axis, int bestBin,
                            Extent* left, Extent* right)
    {
        uint32_t leftCount = 0;
        for (int b = 0; b <= bestBin; ++b)
            if (bins.occupied[axis] >> b & 1) leftCount += bins.count[axis][b];
        BuildTriangle copy[kSmallNode];
        std::copy(tris_.begin() + begin, tris_.begin() + end, copy);
        const V4 inf = {INFINITY, INFINITY, INFINITY, INFINITY};
        V4 leftLo = inf, leftHi = -inf, rightLo = inf, rightHi = -inf;
        uint32_t l = begin, r = begin + leftCount;
        for (uint32_t k = 0; k < end - begin; ++k) {
            bool goesLeft = binIndex[k][axis] <= bestBin;
            tris_[goesLeft ? l : r] = copy[k];
            l += goesLeft;
            r += !goesLeft;
            V4 c = copy[k].centroid();
            I4 toLeft = I4{0, 0, 0, 0} - int32_t(goesLeft); // all ones on the left
            leftLo = vmin(leftLo, V4((I4(c) & toLeft) | (I4(inf) & ~toLeft)));
            leftHi = vmax(leftHi, V4((I4(c) & toLeft) | (I4(-inf) & ~toLeft)));
            rightLo = vmin(rightLo, V4((I4(c) & ~toLeft) | (I4(inf) & toLeft)));
            rightHi = vmax(rightHi, V4((I4(c) & ~toLeft) | (I4(-inf) & toLeft)));
        }
        left->centroids.extend(leftLo, leftHi);
        right->centroids.extend(rightLo, rightHi);
        return begin + leftCount;
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

    LargeArray<BuildTriangle>& tris_;
    NodeArrays& arrays_;
    int parallelDepth_;
    uint32_t packetWidth_;
    double areaScale_;
};

// The lanes of a TrianglePacket4 or TrianglePacket8.
template <typename Packet>
constexpr uint32_t kPacketLanes = sizeof(Packet::triangle) / sizeof(Packet::triangle[0]);

// Writes the packets of BVH positions [begin, begin + count), in order, to
// out[0, ceil(count / lanes)) (appendPackets).
template <typename Packet>
void writePackets(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& order, uint32_t begin,
                  uint32_t count, Packet* out)
{
    constexpr uint32_t width = kPacketLanes<Packet>;
    for (uint32_t p = 0; p * width < count; ++p) {
        Packet& packet = out[p];
        for (uint32_t lane = 0; lane < width; ++lane) {
            uint32_t slot = p * width + lane;
            bool real = slot < count;
            // Padding repeats the packet's first triangle, so no lane is degenerate.
            uint32_t position = begin + (real ? slot : p * width);
            packet.triangle[lane] = real ? int(position) : -1;
            for (int v = 0; v < 3; ++v)
                for (int a = 0; a < 3; ++a) packet.v[v][a][lane] = vertices[3 * order[position] + v][a];
        }
    }
}

// The wide tree from the binary one, as planWide planned it: each wide node
// takes the roots its binary node's plan splits it into, each a leaf or a
// wide node of its own.
//
// Stack bound: a visit pushes at most (children - 1) entries more than it pops,
// so a traversal from a node never holds more than S(node) = (children - 1) +
// max over interior children of S(child), plus one while pushing. A binary
// subtree of height h can always be collapsed with S <= h (two children per
// node), so each node is given a budget, starting at the build's (BVH_STACK_SIZE
// - 1 unless a test asks for less) >= the binary tree's height, and a node
// whose plan would need (children - 1) plus its interior children's largest
// binary height above its budget takes its binary node's two children instead.
//
// In parallel: the top of the tree is collapsed first, with every interior
// child of at most `deferBelow` triangles left as a task; the tasks are
// collapsed on all cores into subtrees of their own (local node and packet
// indices), and each is then copied into place with its indices moved, its
// leaves' packets written there directly. The tree is the one a sequential
// collapse makes; only the order of nodes and packets in memory differs.
class Collapser {
public:
    // A wide subtree still to be collapsed: binary root, stack budget, depth,
    // and the wide node's child slot that will point at it.
    struct Task {
        const BinaryNode* root;
        int budget, depth;
        int parent, slot;
    };
    // A leaf's triangles [begin, begin + count), packed from local packet `first` on.
    struct Leaf {
        uint32_t begin, count, first;
    };

    Collapser(uint32_t packetWidth, uint32_t deferBelow) : packetWidth_(packetWidth), deferBelow_(deferBelow) {}

    std::vector<BvhNode> nodes;
    std::vector<Leaf> leaves;
    uint32_t packetCount = 0;
    std::vector<Task> tasks;
    int depth = 0;

    // Wide node `index` (already allocated) from binary node b, whose stack budget is `budget`.
    void fill(int index, const BinaryNode* b, int budget, int level)
    {
        depth = std::max(depth, level);
        const BinaryNode* children[BVH_WIDTH];
        int k = 0;
        if (b->leaf() || b->count <= packetWidth_) {
            children[k++] = b; // the root of a tiny scene: one leaf
        } else {
            addRoots(b->first, b->wideSplit, children, k);
            addRoots(b->second, BVH_WIDTH - b->wideSplit, children, k);
            int tallest = 0;
            for (int i = 0; i < k; ++i)
                if (!children[i]->asLeaf) tallest = std::max(tallest, children[i]->height);
            if (k - 1 + tallest > budget) {
                k = 0;
                children[k++] = b->first;
                children[k++] = b->second;
            }
        }

        BvhNode node;
        for (int i = 0; i < BVH_WIDTH; ++i) {
            for (int a = 0; a < 3; ++a) {
                node.bounds[a][i] = INFINITY;
                node.bounds[3 + a][i] = -INFINITY;
            }
            node.child[i] = 0; // an empty slot (index 0 is a root, nobody's child)
        }
        for (int i = 0; i < k; ++i) {
            const BinaryNode& c = *children[i];
            for (int a = 0; a < 3; ++a) {
                node.bounds[a][i] = c.bounds.lo[a];
                node.bounds[3 + a][i] = c.bounds.hi[a];
            }
            if (c.asLeaf) {
                node.child[i] = leaf(c.begin, c.count);
            } else if (c.count <= deferBelow_) {
                tasks.push_back({children[i], budget - (k - 1), level + 1, index, i});
            } else {
                node.child[i] = int(nodes.size());
                nodes.emplace_back();
                fill(node.child[i], children[i], budget - (k - 1), level + 1);
            }
        }
        nodes[index] = node;
    }

    // Copies this subtree to nodes[nodeBase...] and writes its packets to
    // packets[packetBase...], moving the indices by those bases.
    template <typename Packet>
    void place(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& order, BvhNode* nodesOut,
               int nodeBase, Packet* packetsOut, int packetBase) const
    {
        for (size_t n = 0; n < nodes.size(); ++n) {
            BvhNode node = nodes[n];
            for (int& c : node.child) {
                if (c > 0) c += nodeBase;
                else if (c < 0) c = ~(~c + 8 * packetBase); // the first packet moves, the count bits stay
            }
            nodesOut[nodeBase + n] = node;
        }
        for (const Leaf& leaf : leaves)
            writePackets(vertices, order, leaf.begin, leaf.count, packetsOut + packetBase + leaf.first);
    }

private:
    // Appends the `roots` roots that n's plan makes of it.
    static void addRoots(const BinaryNode* n, int roots, const BinaryNode** out, int& k)
    {
        int first = n->split[roots - 1];
        if (first == 0) {
            out[k++] = n;
            return;
        }
        addRoots(n->first, first, out, k);
        addRoots(n->second, roots - first, out, k);
    }

    // Reserves packets for triangles [begin, begin + count); returns the child code.
    int leaf(uint32_t begin, uint32_t count)
    {
        uint32_t n = (count + packetWidth_ - 1) / packetWidth_;
        if (n > BVH_LEAF_MAX_PACKETS) throw Error("internal error: a BVH leaf has too many triangles");
        leaves.push_back({begin, count, packetCount});
        packetCount += n;
        return ~int(8 * (packetCount - n) + n - 1);
    }

    uint32_t packetWidth_;
    uint32_t deferBelow_;
};

// The wide tree of the binary tree at `root` into bvh (nodes, packets, depth),
// needing at most stackBudget stack entries.
void collapse(const std::vector<Vec3>& vertices, const BinaryNode* root, int stackBudget, Bvh& bvh)
{
    if (root->height > stackBudget)
        throw Error("internal error: the binary BVH (height " + std::to_string(root->height) +
                    ") is deeper than the traversal stack allows (" + std::to_string(stackBudget) + ")");
    unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    // Tasks of about 1/16 of the triangles per core balance the cores; small
    // scenes are collapsed on one.
    uint32_t deferBelow = threads > 1 && root->count >= kParallelMinTriangles ? root->count / (16 * threads) : 0;
    const uint32_t width = uint32_t(bvh.packetWidth());
    std::vector<Collapser> parts(1, Collapser(width, deferBelow)); // the top, then a part per task
    parts[0].nodes.emplace_back();
    parts[0].fill(0, root, stackBudget, 1);
    const std::vector<Collapser::Task> tasks = std::move(parts[0].tasks);
    parts.resize(1 + tasks.size(), Collapser(width, 0));
    parallelFor(tasks.size(), [&](size_t i) {
        Collapser& part = parts[1 + i];
        part.nodes.emplace_back();
        part.fill(0, tasks[i].root, tasks[i].budget, tasks[i].depth);
    });

    std::vector<int> nodeBase(parts.size()), packetBase(parts.size());
    size_t nodeCount = 0, packetCount = 0;
    for (size_t p = 0; p < parts.size(); ++p) {
        nodeBase[p] = int(nodeCount);
        packetBase[p] = int(packetCount);
        nodeCount += parts[p].nodes.size();
        packetCount += parts[p].packetCount;
        bvh.depth = std::max(bvh.depth, parts[p].depth);
    }
    if (packetCount > size_t(INT32_MAX >> 3)) throw Error("too many triangles for the BVH's leaf encoding");
    for (size_t i = 0; i < tasks.size(); ++i) parts[0].nodes[tasks[i].parent].child[tasks[i].slot] = nodeBase[1 + i];
    bvh.nodes.resize(nodeCount);
    std::visit(
        [&](auto& packets) {
            packets.resize(packetCount);
            parallelFor(parts.size(), [&](size_t p) {
                parts[p].place(vertices, bvh.triangleOrder, bvh.nodes.data(), nodeBase[p], packets.data(),
                               packetBase[p]);
            });
        },
        bvh.packets);
}

// Σ over the subtree's nodes of area(node) · (traversal cost, or triangles for a leaf).
double sahCost(const BinaryNode* n)
{
    double own = n->bounds.surfaceArea() * (n->leaf() ? double(n->count) : double(kTraversalCost));
    return n->leaf() ? own : own + sahCost(n->first) + sahCost(n->second);
}

} // namespace

// Whether Linux gives an madvise'd region huge pages without stopping the
// faulting thread to compact memory first: not under its default defrag
// setting, "madvise", nor "always" and "defer+madvise", which compact
// synchronously for such regions; with "defer" or "never" a fault takes a huge
// page if one is free and a 4 KiB page otherwise. On a virtual machine whose
// memory needed compacting, huge pages made the first build of the
// 1M-triangle displaced sphere in a process 0.34-0.46 s against 0.27-0.28 s.
static bool hugePagesWithoutStall()
{
    static const bool answer = [] {
        std::ifstream f("/sys/kernel/mm/transparent_hugepage/defrag");
        std::string line;
        std::getline(f, line);
        return line.find("[defer]") != std::string::npos || line.find("[never]") != std::string::npos;
    }();
    return answer;
}

void* allocateLargeArray(size_t bytes)
{
    constexpr size_t kHugePage = size_t(2) << 20;
    void* p = nullptr;
    if (bytes >= kHugePage) {
        size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
        p = std::aligned_alloc(kHugePage, rounded);
#ifdef MADV_HUGEPAGE
        if (p && hugePagesWithoutStall()) madvise(p, rounded, MADV_HUGEPAGE); // advice only
#endif
    } else {
        p = std::malloc(std::max<size_t>(bytes, 1));
    }
    if (!p) throw std::bad_alloc();
    return p;
}

template <typename Packet>
void appendPackets(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& order, uint32_t begin,
                   uint32_t count, std::vector<Packet>& packets)
{
    constexpr uint32_t width = kPacketLanes<Packet>;
    size_t first = packets.size();
    packets.resize(first + (count + width - 1) / width);
    writePackets(vertices, order, begin, count, packets.data() + first);
}

template void appendPackets(const std::vector<Vec3>&, const std::vector<uint32_t>&, uint32_t, uint32_t,
                            std::vector<TrianglePacket4>&);
template void appendPackets(const std::vector<Vec3>&, const std::vector<uint32_t>&, uint32_t, uint32_t,
                            std::vector<TrianglePacket8>&);

Bvh buildBvh(const std::vector<Vec3>& vertices, int packetWidth, int stackBudget)
{
    auto start = std::chrono::steady_clock::now();
    if (packetWidth != 4 && packetWidth != 8)
        throw Error("internal error: triangle packets are 4 or 8 wide, not " + std::to_string(packetWidth));
    size_t count = vertices.size() / 3;
    if (count == 0) throw Error("cannot build a BVH over no triangles");
    if (count > size_t(INT32_MAX) / 3) throw Error("too many triangles for 32-bit indices");
    LargeArray<BuildTriangle> tris(count);
    constexpr size_t kChunks = 64;
    std::vector<Extent> chunkExtent(kChunks);
    parallelFor(kChunks, [&](size_t chunk) {
        Extent& e = chunkExtent[chunk];
        for (size_t t = count * chunk / kChunks; t < count * (chunk + 1) / kChunks; ++t) {
            Bounds box;
            for (int k = 0; k < 3; ++k) box.extend(vertices[3 * t + k]);
            V4 lo = {box.lo.x, box.lo.y, box.lo.z, 0}, hi = {box.hi.x, box.hi.y, box.hi.z, 0};
            tris[t].lo = lo;
            tris[t].hiAndIndex = V4(I4(hi) | I4{0, 0, 0, int32_t(t)});
            V4 c = tris[t].centroid();
            e.bounds.extend(lo, hi);
            e.centroids.extend(c, c);
        }
    });
    Extent all;
    for (const Extent& e : chunkExtent) {
        all.bounds.extend(e.bounds);
        all.centroids.extend(e.centroids);
    }
    // Four levels more than the cores need: splits near the root are often
    // uneven, and more, smaller subtrees balance the cores. (With two more,
    // the 1M-triangle displaced sphere's binary build kept 1.6 of 2 cores
    // busy and took 0.29-0.34 s; with four, 0.25-0.27 s.)
    int parallelDepth = 4;
    for (unsigned threads = std::max(1u, std::thread::hardware_concurrency()); (1u << (parallelDepth - 4)) < threads;)
        ++parallelDepth;
    NodeArrays arrays;
    Builder builder(tris, arrays, parallelDepth, all.bounds.bounds(), uint32_t(packetWidth));
    const BinaryNode* root = builder.node(arrays.add(count), 0, uint32_t(count), all, 0);
    // The SAH cost, a walk of the whole binary tree that only --stats
    // reads, is summed beside the collapse.
    std::future<double> cost = std::async(std::launch::async, [root] { return sahCost(root); });
    Bvh bvh;
    if (packetWidth == 8) bvh.packets = LargeArray<TrianglePacket8>();
    bvh.triangleOrder.resize(count);
    parallelFor(kChunks, [&](size_t chunk) {
        for (size_t i = count * chunk / kChunks; i < count * (chunk + 1) / kChunks; ++i)
            bvh.triangleOrder[i] = tris[i].index();
    });
    bvh.binaryHeight = root->height;
    collapse(vertices, root, stackBudget, bvh);
    double rootArea = root->bounds.surfaceArea();
    bvh.sahCost = rootArea > 0 ? cost.get() / rootArea : 0;
    bvh.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

} // namespace wv
