// Binned-SAH build of TriangleBvh. Subtrees above a size threshold are built on their own thread
// into their own node array and appended afterwards, which reproduces the serial layout exactly:
// the tree, and therefore every query, does not depend on the thread count or on which thread
// built what.
#include "gimg/geometry/bvh.h"

#include "gimg/geometry/parallel_for.h"

#include <glm/common.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <exception>
#include <limits>
#include <stdexcept>
#include <thread>

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace gimg::geo {

void advise_huge_pages(void* memory, std::size_t bytes) noexcept {
#ifdef __linux__
    constexpr std::uintptr_t kHuge = std::uintptr_t(2) << 20;
    if (bytes < 2 * kHuge) return;
    const auto begin = (reinterpret_cast<std::uintptr_t>(memory) + kHuge - 1) & ~(kHuge - 1);
    const auto end = (reinterpret_cast<std::uintptr_t>(memory) + bytes) & ~(kHuge - 1);
    // Advice only: where transparent huge pages are off, the memory stays in small pages.
    if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)memory;
    (void)bytes;
#endif
}

namespace {

constexpr int kBins = 16;
// Below this depth every split is SAH; deeper (pathological inputs) splits at the object median,
// which halves the range, so no tree is deeper than kMedianSplitDepth + log2(F) < kMaxBvhDepth.
constexpr int kMedianSplitDepth = 64;
// Subtrees smaller than this are not worth a thread; one of 2,048 triangles takes about 0.6 ms to
// build, much more than starting a thread.
constexpr std::size_t kParallelSubtree = 2048;

// Outward rounding to float: the float box contains the double one (out-of-range values become
// infinite, which still contains them).
glm::vec3 round_down(const glm::dvec3& v) {
    glm::vec3 out;
    for (int i = 0; i < 3; ++i) {
        if (v[i] < -double(std::numeric_limits<float>::max())) {
            out[i] = -std::numeric_limits<float>::infinity();
            continue;
        }
        float f = static_cast<float>(std::min(v[i], double(std::numeric_limits<float>::max())));
        if (double(f) > v[i]) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
        out[i] = f;
    }
    return out;
}

glm::vec3 round_up(const glm::dvec3& v) { return -round_down(-v); }

// Boxes in float, each triangle's rounded outward from its double corners: the union of such boxes
// is the outward rounding of the double union (rounding is monotone), so the nodes' bounds are what
// a double build would give, with half the memory to sweep.
struct Box {
    glm::vec3 lo{std::numeric_limits<float>::infinity()};
    glm::vec3 hi{-std::numeric_limits<float>::infinity()};
    void grow(const glm::vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void grow(const Box& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    double half_area() const {
        const glm::dvec3 d = glm::dvec3(hi) - glm::dvec3(lo);
        return d.x < 0.0 ? 0.0 : d.x * d.y + d.y * d.z + d.z * d.x;
    }
};

// Four float lanes (x, y, z and an ignored fourth) for binning, where each triangle updates three
// bins: one vector min and max instead of six scalar ones. The comparisons are glm::min's and
// glm::max's, so bins hold exactly the floats a Box would.
using Lanes = float __attribute__((vector_size(16)));

struct PrimRef {
    Box box;
    float after_hi = 0.0f;  // hi_lanes()'s fourth lane: a float, never a denormal from the face bits
    std::uint32_t face;
    glm::vec3 centroid() const { return 0.5f * (box.lo + box.hi); }
    // The box's corners as lanes, with the next float (hi.x, after_hi) in the fourth.
    Lanes lo_lanes() const { return lanes_at(offsetof(PrimRef, box) + offsetof(Box, lo)); }
    Lanes hi_lanes() const { return lanes_at(offsetof(PrimRef, box) + offsetof(Box, hi)); }
    Lanes lanes_at(std::size_t offset) const {
        Lanes out;
        std::memcpy(&out, reinterpret_cast<const char*>(this) + offset, sizeof out);
        return out;
    }
};
static_assert(offsetof(PrimRef, box) + offsetof(Box, hi) + sizeof(Lanes) <= sizeof(PrimRef));
using PrimRefs = std::vector<PrimRef, UninitializedAllocator<PrimRef>>;

struct Range {
    std::size_t begin, end;
    Box bounds;           // of the triangles
    Box centroid_bounds;  // of their box centroids
    std::size_t size() const { return end - begin; }
};

struct Split {
    int axis = -1;
    int bin = 0;  // primitives with bin index <= this go left
    double cost = std::numeric_limits<double>::infinity();
    Box left, right;
};

struct Bin {
    Lanes lo, hi;
    std::uint32_t count;
    void clear() {
        lo = Lanes{} + std::numeric_limits<float>::infinity();
        hi = -lo;
        count = 0;
    }
    void grow(Lanes plo, Lanes phi) {
        lo = plo < lo ? plo : lo;
        hi = hi < phi ? phi : hi;
        ++count;
    }
    Box box() const { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
};

class BvhBuilder {
public:
    BvhBuilder(PrimRefs& prims, const Mesh& mesh, std::vector<std::uint32_t>& kept_face, const BvhBuildOptions& options,
               unsigned threads)
        : prims_(prims), mesh_(mesh), kept_face_(kept_face), options_(options), threads_(threads) {}

    // A thread for the right subtree whenever fewer than `threads` are building, at any depth: SAH
    // splits are uneven, so threads handed out by depth alone sit idle once their smaller subtrees
    // are done. A thread waiting for its worker does not count.
    bool take_thread() {
        unsigned n = building_.load();
        while (n < threads_)
            if (building_.compare_exchange_weak(n, n + 1)) return true;
        return false;
    }

    void build_node(std::uint32_t index, Range range, BvhNodeArray& nodes, int depth) {
        nodes[index].bounds_min = range.bounds.lo;
        nodes[index].bounds_max = range.bounds.hi;
        const glm::vec3 extent = range.centroid_bounds.hi - range.centroid_bounds.lo;
        if (range.size() > options_.max_leaf_size && !(extent.x > 0.0 || extent.y > 0.0 || extent.z > 0.0))
            range.end = drop_copies(range);
        const std::size_t n = range.size();
        Range left, right;
        if (!split(range, depth, left, right)) {
            nodes[index].first = static_cast<std::uint32_t>(range.begin);
            nodes[index].count = static_cast<std::uint32_t>(n);
            return;
        }
        const auto child = static_cast<std::uint32_t>(nodes.size());
        nodes.resize(nodes.size() + 2);  // nodes.size() stays even: pairs share a cache line
        nodes[index].first = child;
        nodes[index].count = 0;
        if (right.size() >= kParallelSubtree && take_thread()) {
            BvhNodeArray right_nodes(1);  // its root; its pairs then start at odd indices
            right_nodes.reserve(2 * right.size() + 1);  // as nodes_ in the constructor
            std::exception_ptr worker_error;
            std::thread worker([&] {
                try {
                    build_node(0, right, right_nodes, depth + 1);
                } catch (...) {
                    worker_error = std::current_exception();
                }
                --building_;
            });
            try {
                build_node(child, left, nodes, depth + 1);
            } catch (...) {
                worker.join();
                throw;
            }
            --building_;
            worker.join();
            ++building_;
            if (worker_error) std::rethrow_exception(worker_error);
            // right_nodes[i], i >= 1, lands at nodes[base + i] (base odd, so pairs stay at even
            // indices); right_nodes[0] is the child slot.
            const auto base = static_cast<std::uint32_t>(nodes.size() - 1);
            for (BvhNode& node : right_nodes)
                if (!node.is_leaf()) node.first += base;
            nodes[child + 1] = right_nodes[0];
            nodes.insert(nodes.end(), right_nodes.begin() + 1, right_nodes.end());
        } else {
            build_node(child, left, nodes, depth + 1);
            build_node(child + 1, right, nodes, depth + 1);
        }
    }

private:
    // Faces with the same centroid: copies of one triangle (its three corners at the same points, in
    // any order) keep only the lowest face index, which is the one every query reports at a tie,
    // so queries never test thousands of copies. Returns the new end of the range; the copies sit
    // after it, in slots no node names, and kept_face_ names the kept face of each.
    std::size_t drop_copies(const Range& range) {
        using Key = std::array<glm::dvec3, 3>;
        auto key_of = [&](const PrimRef& p) {
            const glm::uvec3& t = mesh_.triangles[p.face];
            Key k{mesh_.positions[t.x], mesh_.positions[t.y], mesh_.positions[t.z]};
            std::sort(k.begin(), k.end(), [](const glm::dvec3& a, const glm::dvec3& b) {
                return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
            });
            return k;
        };
        auto less = [](const Key& a, const Key& b) {
            for (int i = 0; i < 3; ++i)
                for (int c = 0; c < 3; ++c)
                    if (a[i][c] != b[i][c]) return a[i][c] < b[i][c];
            return false;
        };
        std::vector<std::pair<Key, PrimRef>> items;
        items.reserve(range.size());
        for (std::size_t i = range.begin; i < range.end; ++i) items.push_back({key_of(prims_[i]), prims_[i]});
        std::sort(items.begin(), items.end(), [&](const auto& a, const auto& b) {
            return less(a.first, b.first) || (!less(b.first, a.first) && a.second.face < b.second.face);
        });
        std::size_t kept = range.begin, copies = range.end;
        std::vector<PrimRef> dropped;
        for (std::size_t i = 0; i < items.size(); ++i) {
            if (i > 0 && !less(items[i - 1].first, items[i].first)) {
                kept_face_[items[i].second.face] = kept_face_[items[i - 1].second.face];
                dropped.push_back(items[i].second);
            } else {
                kept_face_[items[i].second.face] = items[i].second.face;
                prims_[kept++] = items[i].second;
            }
        }
        copies -= dropped.size();
        std::copy(dropped.begin(), dropped.end(), prims_.begin() + std::ptrdiff_t(copies));
        return kept;
    }

    // Bin of a centroid among `bins`; NaN (an infinite coordinate) goes to bin 0.
    static int bin_of(float c, float lo, float scale, int bins) { return bin_index((c - lo) * scale, bins); }
    static int bin_index(float x, int bins) {  // branch-free: a clamp, then the truncation
        return static_cast<int>(std::min(x > 0.0f ? x : 0.0f, float(bins - 1)));
    }

    // Chooses and performs a split of `range`; false makes it a leaf.
    bool split(const Range& range, int depth, Range& left, Range& right) {
        const std::size_t n = range.size();
        // A range of a few triangles is a leaf: splitting it would save the walks little and make
        // the tree's most numerous nodes.
        if (n <= options_.max_leaf_size) return false;
        const glm::vec3 extent = range.centroid_bounds.hi - range.centroid_bounds.lo;
        const bool all_centroids_equal = !(extent.x > 0.0f || extent.y > 0.0f || extent.z > 0.0f);
        if (all_centroids_equal || depth >= kMedianSplitDepth) return median_split(range, left, right);

        // One sweep over the range bins it along all three axes; a range of fewer than kBins
        // triangles gets as many bins as triangles, since evaluating the planes costs more than
        // binning there, and most ranges are small.
        const int nb = int(std::min<std::size_t>(n, kBins));
        std::array<float, 3> scale{};
        for (int axis = 0; axis < 3; ++axis)
            scale[axis] = extent[axis] > 0.0f && std::isfinite(extent[axis]) ? float(nb) / extent[axis] : 0.0f;
        const glm::vec3 lo = range.centroid_bounds.lo;
        std::array<std::array<Bin, kBins>, 3> bins;  // the first nb of each axis are used
        for (auto& axis_bins : bins)
            for (int b = 0; b < nb; ++b) axis_bins[b].clear();
        const Lanes lo4 = {lo.x, lo.y, lo.z, 0.0f}, scale4 = {scale[0], scale[1], scale[2], 0.0f};
        for (std::size_t i = range.begin; i < range.end; ++i) {
            const PrimRef& p = prims_[i];
            const Lanes plo = p.lo_lanes(), phi = p.hi_lanes();
            const Lanes x = (0.5f * (plo + phi) - lo4) * scale4;  // bin_of's, per axis
            for (int axis = 0; axis < 3; ++axis)
                bins[axis][bin_index(x[axis], nb)].grow(plo, phi);
        }
        Split best;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(scale[axis] > 0.0f)) continue;
            const std::array<Bin, kBins>& axis_bins = bins[axis];
            // Sweep from the right, then evaluate each plane from the left.
            std::array<double, kBins> right_cost{};
            Box acc;
            std::size_t count = 0;
            for (int b = nb - 1; b > 0; --b) {
                acc.grow(axis_bins[b].box());
                count += axis_bins[b].count;
                right_cost[b] = acc.half_area() * double(count);
            }
            acc = Box{};
            count = 0;
            for (int b = 0; b < nb - 1; ++b) {
                acc.grow(axis_bins[b].box());
                count += axis_bins[b].count;
                if (count == 0 || count == n) continue;
                const double cost = acc.half_area() * double(count) + right_cost[b + 1];
                if (cost < best.cost) {
                    best.cost = cost;
                    best.axis = axis;
                    best.bin = b;
                }
            }
        }
        if (best.axis < 0) return median_split(range, left, right);
        for (int b = 0; b < nb; ++b) (b <= best.bin ? best.left : best.right).grow(bins[best.axis][b].box());

        const int axis = best.axis;
        left = {range.begin, range.end, best.left, {}};
        right = {range.end, range.end, best.right, {}};
        // Hoare's partition (std::partition's, so the order is the same), each triangle's centroid
        // joining its side's bounds as it is classified: one sweep instead of two.
        auto goes_left = [&](std::size_t i) {
            const glm::vec3 c = prims_[i].centroid();
            const bool is_left = bin_of(c[axis], lo[axis], scale[axis], nb) <= best.bin;
            (is_left ? left : right).centroid_bounds.grow(c);
            return is_left;
        };
        std::size_t first = range.begin, last = range.end;
        for (;;) {
            while (first != last && goes_left(first)) ++first;
            if (first == last) break;
            --last;
            while (first != last && !goes_left(last)) --last;
            if (first == last) break;
            std::swap(prims_[first], prims_[last]);
            ++first;
        }
        left.end = right.begin = first;
        return true;
    }

    // Halves the range at the median centroid along the widest centroid axis (by face index when
    // all centroids coincide), so the result never depends on the sort's internal order.
    bool median_split(const Range& range, Range& left, Range& right) {
        const glm::vec3 extent = range.centroid_bounds.hi - range.centroid_bounds.lo;
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (extent[a] > extent[axis]) axis = a;
        const std::size_t m = range.begin + range.size() / 2;
        std::nth_element(prims_.begin() + std::ptrdiff_t(range.begin), prims_.begin() + std::ptrdiff_t(m),
                         prims_.begin() + std::ptrdiff_t(range.end), [&](const PrimRef& x, const PrimRef& y) {
                             const float cx = x.centroid()[axis], cy = y.centroid()[axis];
                             return cx != cy ? cx < cy : x.face < y.face;
                         });
        left = {range.begin, m, {}, {}};
        right = {m, range.end, {}, {}};
        for (Range* r : {&left, &right})
            for (std::size_t i = r->begin; i < r->end; ++i) {
                r->bounds.grow(prims_[i].box);
                r->centroid_bounds.grow(prims_[i].centroid());
            }
        return true;
    }

    PrimRefs& prims_;
    const Mesh& mesh_;
    std::vector<std::uint32_t>& kept_face_;
    const BvhBuildOptions& options_;
    unsigned threads_;
    std::atomic<unsigned> building_{1};  // threads building now, this one included
};

}  // namespace

float bvh_extent(const BvhNodeArray& nodes) {
    float e = 0.0f;
    for (int a = 0; !nodes.empty() && a < 3; ++a)
        e = std::max({e, std::abs(nodes[0].bounds_min[a]), std::abs(nodes[0].bounds_max[a])});
    return e;
}

BvhLayout build_bvh_layout(const Mesh& mesh, const BvhBuildOptions& options) {
    const std::size_t fcount = mesh.face_count();
    if (fcount >= std::numeric_limits<std::uint32_t>::max() / 2)
        throw std::length_error("mesh too large for a 32-bit BVH");
    if (options.max_leaf_size == 0) throw std::invalid_argument("BVH max_leaf_size must be >= 1");
    for (const glm::uvec3& t : mesh.triangles)
        if (t.x >= mesh.vertex_count() || t.y >= mesh.vertex_count() || t.z >= mesh.vertex_count())
            throw std::invalid_argument("BVH: a triangle names a vertex index past the vertex count");
    BvhLayout out;
    if (fcount == 0) return out;
    const unsigned threads = options.threads ? options.threads : default_thread_count();

    PrimRefs prims(fcount);
    parallel_for_chunks(
        fcount, 65536,
        [&](std::size_t, std::size_t begin, std::size_t end) {
            for (std::size_t f = begin; f < end; ++f) {
                const glm::uvec3& t = mesh.triangles[f];
                const glm::dvec3 &a = mesh.positions[t.x], &b = mesh.positions[t.y], &c = mesh.positions[t.z];
                PrimRef& p = prims[f];
                p.box = {round_down(glm::min(glm::min(a, b), c)), round_up(glm::max(glm::max(a, b), c))};
                p.face = static_cast<std::uint32_t>(f);
            }
        },
        threads);
    Range root{0, fcount, {}, {}};
    for (const PrimRef& p : prims) {
        root.bounds.grow(p.box);
        root.centroid_bounds.grow(p.centroid());
    }

    // Room for the largest tree (a leaf per triangle), so the array never moves while it grows. It
    // is not shrunk afterwards: pages of the reservation the tree never reaches are never touched,
    // while a shrinking copy faults in every page again (0.1-0.2 s at 1M faces on these VMs).
    out.nodes.reserve(2 * fcount + 2);
    out.nodes.resize(2);  // root and padding
    out.kept_face.assign(fcount, std::numeric_limits<std::uint32_t>::max());
    BvhBuilder builder(prims, mesh, out.kept_face, options, threads);
    builder.build_node(0, root, out.nodes, 0);
    for (std::size_t f = 0; f < fcount; ++f)
        if (out.kept_face[f] == std::numeric_limits<std::uint32_t>::max()) out.kept_face[f] = std::uint32_t(f);
    out.face_order.resize(fcount);
    for (std::size_t i = 0; i < fcount; ++i) out.face_order[i] = prims[i].face;
    return out;
}

TriangleBvh::TriangleBvh(const Mesh& mesh, const BvhBuildOptions& options) {
    BvhLayout layout = build_bvh_layout(mesh, options);
    nodes_ = std::move(layout.nodes);
    face_order_ = std::move(layout.face_order);
    const std::size_t fcount = face_order_.size();
    slot_of_face_.resize(fcount);
    triangles_.resize(fcount);
    parallel_for_chunks(
        fcount, 65536,
        [&](std::size_t, std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                const std::uint32_t f = face_order_[i];
                const glm::uvec3& t = mesh.triangles[f];
                slot_of_face_[f] = static_cast<std::uint32_t>(i);
                triangles_[i] = {mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
            }
        },
        options.threads);
    const std::vector<std::uint32_t>& kept = layout.kept_face;
    for (std::size_t f = 0; f < fcount; ++f)
        if (kept[f] != f) {
            copy_slots_[kept[f]].push_back(slot_of_face_[f]);
            slot_of_face_[f] = slot_of_face_[kept[f]];
        }
}

}  // namespace gimg::geo
