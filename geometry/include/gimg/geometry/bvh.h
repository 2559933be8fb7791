#pragma once
// Bounding-volume hierarchy over the triangles of a Mesh: binned-SAH build into one flat node
// array (parallel over subtrees), exact closest-point queries and ray queries. Queries are const
// and thread-safe; results do not depend on traversal order (ties go to the lowest face index),
// so they equal a brute-force scan over all faces.

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/mesh.h"
#include "gimg/geometry/triangle_queries.h"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

namespace gimg::geo {

// 32 bytes, laid out for upload as it is (std430: vec3 + uint, vec3 + uint). Bounds are float,
// rounded outward from the double-precision triangles, so a box always contains its triangles;
// queries stay exact because leaves test the double-precision triangles. Float boxes halve the
// tree's memory (1M triangles: ~32 MB of nodes) and let a sibling pair share one cache line.
struct alignas(32) BvhNode {
    glm::vec3 bounds_min{0.0f};
    // Leaf (count > 0): triangles [first, first + count) of TriangleBvh's BVH order.
    // Inner node (count == 0): its children are nodes `first` and `first + 1`.
    std::uint32_t first = 0;
    glm::vec3 bounds_max{0.0f};
    std::uint32_t count = 0;
    bool is_leaf() const { return count > 0; }
};
static_assert(sizeof(BvhNode) == 32);

// Asks the kernel (Linux) to back the 2 MiB-aligned part of a fresh allocation of at least 4 MiB
// with huge pages on first touch: a build of 1.2M faces first-touches about 21,000 4 KB pages,
// each fault costing microseconds on a virtual machine. Nothing elsewhere, or for smaller ones.
void advise_huge_pages(void* memory, std::size_t bytes) noexcept;

// Allocates the node array on a 64-byte boundary. Node 0 is the root and node 1 unused padding,
// so every sibling pair (2k, 2k + 1) shares one cache line.
template <class T>
struct CacheLineAllocator {
    using value_type = T;
    static constexpr std::align_val_t kAlignment{64};
    CacheLineAllocator() = default;
    template <class U>
    CacheLineAllocator(const CacheLineAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        T* p = static_cast<T*>(::operator new(n * sizeof(T), kAlignment));
        advise_huge_pages(p, n * sizeof(T));
        return p;
    }
    void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, kAlignment); }
    template <class U>
    bool operator==(const CacheLineAllocator<U>&) const noexcept {
        return true;
    }
};
using BvhNodeArray = std::vector<BvhNode, CacheLineAllocator<BvhNode>>;

// Leaves the elements a resize adds uninitialised, for arrays filled right after (in parallel), so
// that their pages are first touched by the threads that fill them and not by a serial zeroing;
// large ones in huge pages where the system has them.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = UninitializedAllocator<U>;
    };
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        T* p = std::allocator<T>::allocate(n);
        advise_huge_pages(p, n * sizeof(T));
        return p;
    }
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

struct BvhBuildOptions {
    std::uint32_t max_leaf_size = 4;  // ranges of at most this many triangles are leaves, never larger
    unsigned threads = 0;             // 0: default_thread_count()
};

// The tree alone, as the builder leaves it: the nodes and the faces in BVH order. For callers that
// keep the triangles in a layout of their own (the GPU ray caster); TriangleBvh adds its copies.
struct BvhLayout {
    BvhNodeArray nodes;
    // BVH order -> original face index. Copies of a triangle (the same three corners) sit in slots
    // no leaf names.
    std::vector<std::uint32_t> face_order;
    // Original face index -> the face answering for it: itself, or the kept face it is a copy of.
    std::vector<std::uint32_t> kept_face;
};
// Throws std::invalid_argument for a triangle naming a vertex past the vertex count and
// std::length_error past 2^31 faces.
BvhLayout build_bvh_layout(const Mesh& mesh, const BvhBuildOptions& options = {});

// The largest |coordinate| of the root box (0 for an empty tree): the ray box test widens boxes by
// 2^-18 of it (bvh_query.cpp), and the GPU ray caster passes it to its shader.
float bvh_extent(const BvhNodeArray& nodes);

struct ClosestPointResult {
    double distance = std::numeric_limits<double>::infinity();
    glm::dvec3 point{0.0};
    std::uint32_t face = kInvalidIndex;     // kInvalidIndex: nothing within the search radius
    glm::dvec3 barycentric{1.0, 0.0, 0.0};  // weights of the face's corners 0, 1, 2
    bool found() const { return face != kInvalidIndex; }
};

struct RayHit {
    double t = std::numeric_limits<double>::infinity();
    std::uint32_t face = kInvalidIndex;
    glm::dvec3 barycentric{1.0, 0.0, 0.0};
};

class TriangleBvh {
public:
    TriangleBvh() = default;
    // Copies the triangles' corner positions (in BVH order), so `mesh` may go away afterwards.
    explicit TriangleBvh(const Mesh& mesh, const BvhBuildOptions& options = {});

    // Closest point of the surface to p: the minimum over all faces of the exact point-triangle
    // distance, ties broken by the lowest face index. Faces farther than max_distance are
    // ignored (result.found() is false when all are). `hint_face`, e.g. the answer for a nearby
    // query point, only speeds the search up: it seeds the search radius and never changes the
    // result.
    ClosestPointResult closest_point(const glm::dvec3& p, double max_distance = std::numeric_limits<double>::infinity(),
                                     std::uint32_t hint_face = kInvalidIndex) const;

    // Nearest hit with t in [ray.t_min, ray.t_max] (ties: lowest face index), or nullopt.
    std::optional<RayHit> intersect_nearest(const Ray& ray) const;
    // Whether any face is hit in [ray.t_min, ray.t_max]; stops at the first hit found.
    bool intersect_any(const Ray& ray) const;
    // Every hit in [ray.t_min, ray.t_max], sorted by (t, face). A ray through a shared edge or
    // corner reports each face it touches (callers counting crossings must merge those).
    std::vector<RayHit> intersect_all(const Ray& ray) const;
    // How often the ray crosses the surface in [ray.t_min, ray.t_max]: intersect_all's hits with
    // those less than 1e-12 apart in t counted once, so a ray through a shared edge or corner of a
    // closed mesh crosses it once (parity tells inside from outside).
    std::uint32_t crossings(const Ray& ray) const;

    struct Triangle {
        glm::dvec3 a, b, c;
    };
    const BvhNodeArray& nodes() const { return nodes_; }
    float extent() const { return bvh_extent(nodes_); }
    // Corner positions in BVH order (the slots the leaves name; copies of a triangle sit in slots
    // no leaf names).
    std::span<const Triangle> triangles() const { return triangles_; }
    // BVH order -> original face index.
    const std::vector<std::uint32_t>& face_order() const { return face_order_; }
    std::size_t face_count() const { return face_order_.size(); }
    bool empty() const { return face_order_.empty(); }

private:
    BvhNodeArray nodes_;
    std::vector<std::uint32_t> face_order_;
    std::vector<std::uint32_t> slot_of_face_;                            // original face index -> BVH order
    std::vector<Triangle, UninitializedAllocator<Triangle>> triangles_;  // corner positions in BVH order
    // Copies of a triangle (the same three corners) are left out of the tree; a kept face's
    // copies, by slot, for intersect_all, which reports every face.
    std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> copy_slots_;
};

}  // namespace gimg::geo
