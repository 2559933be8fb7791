// build_polycube: steps 1 to 3 in order, with the connectivity check that inserts a plane where a
// slab of the polycube does not join the same contours as the mesh's slab.
#include "polycube_parts.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/topology.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <functional>
#include <numeric>
#include <optional>
#include <set>
#include <tuple>

namespace gimg::passes {

namespace {

using namespace polycube;

// Moves a plane off the vertices' heights when one lies within `eps` of it (the cut would leave
// slivers or pass through a vertex): to the height within `window` farthest from every vertex.
double clear_of_vertices(double z, const std::vector<double>& zv, double eps, double window) {
    const auto clearance = [&](double h) {
        const auto it = std::lower_bound(zv.begin(), zv.end(), h);
        double d = 1e300;
        if (it != zv.end()) d = *it - h;
        if (it != zv.begin()) d = std::min(d, h - *(it - 1));
        return d;
    };
    if (clearance(z) >= eps) return z;
    std::vector<double> candidates{z - window, z + window};
    const auto lo = std::lower_bound(zv.begin(), zv.end(), z - window),
               hi = std::upper_bound(zv.begin(), zv.end(), z + window);
    for (auto a = lo; a != hi && a + 1 != hi; ++a) candidates.push_back(0.5 * (a[0] + a[1]));
    double best = z, score = -1.0;
    for (double h : candidates) {
        const double c = clearance(h);
        if (c > score || (c == score && std::abs(h - z) < std::abs(best - z))) score = c, best = h;
    }
    return best;
}

using Clock = std::chrono::steady_clock;

// A retry still running when the attempts' time (PolycubeOptions::retry_seconds) is spent stops at
// its next check: the first attempt's failure is then returned, as when no retry starts.
struct OutOfTime {};
void check_time(const std::optional<Clock::time_point>& stop_at) {
    if (stop_at && Clock::now() > *stop_at) throw OutOfTime{};
}

long long euler(const geo::MeshInfo& info) {
    long long chi = 0;
    for (const auto& c : info.component_info) chi += c.euler_characteristic;
    return chi;
}

// The construction with the planes normal to z, stopped by OutOfTime after `stop_at`.
Polycube build_along_z(Context* ctx, const geo::Mesh& input, const PolycubeOptions& o,
                       const std::optional<Clock::time_point>& stop_at) {
    const auto started = Clock::now();
    if (!(o.dz >= 0.0) || !std::isfinite(o.dz)) throw geo::InputError("--dz must be a finite number >= 0");
    if (!(o.da > 0.0) || !std::isfinite(o.da)) throw geo::InputError("--da must be a finite number > 0");
    if (o.max_level > 10) throw geo::InputError("the quadtree level must be at most 10");
    if (o.k < 1) throw geo::InputError("--k must be at least 1");
    CappedMesh capped = cap_holes(input);
    geo::Mesh& mesh = capped.mesh;
    double volume = 0.0;
    for (const auto& t : mesh.triangles)
        volume += glm::dot(mesh.positions[t[0]], glm::cross(mesh.positions[t[1]], mesh.positions[t[2]]));
    // A flat mesh, its holes capped, is two coincident sheets: every plane cuts it in loops of no
    // area, which no slicing axis can turn into a polyhedron.
    const double diagonal = mesh.bounds().diagonal();
    if (!(std::abs(volume) > 1e-9 * diagonal * diagonal * diagonal))
        throw geo::InputError("the mesh is flat: closed off, it encloses no volume, and a polycube needs some");
    if (volume < 0.0)  // the construction assumes outward faces
        for (auto& t : mesh.triangles) std::swap(t[1], t[2]);

    // The mesh's own positions; the construction may follow a smoothed copy (same faces).
    std::vector<glm::dvec3> true_positions = mesh.positions;
    if (o.slice_smoothing > 0) {
        std::vector<std::vector<std::uint32_t>> ring(mesh.vertex_count());
        for (const auto& t : mesh.triangles)
            for (int k = 0; k < 3; ++k) ring[t[k]].push_back(t[(k + 1) % 3]);  // each edge once per side
        for (std::uint32_t sweep = 0; sweep < o.slice_smoothing; ++sweep) {
            std::vector<glm::dvec3> next = mesh.positions;
            for (std::size_t v = 0; v < ring.size(); ++v) {
                glm::dvec3 mean(0.0);
                for (std::uint32_t u : ring[v]) mean += mesh.positions[u];
                next[v] = 0.5 * (mesh.positions[v] + mean / double(ring[v].size()));
            }
            mesh.positions = std::move(next);
        }
    }
    Polycube out;
    PolycubeStatistics& st = out.stats;
    const geo::MeshInfo info = geo::analyze_topology(mesh);
    st.genus = std::size_t((2 - euler(info)) / 2);
    st.holes = capped.loops;
    const geo::Bounds box = mesh.bounds();
    const double height = box.max.z - box.min.z;
    if (!(height > 0.0)) throw geo::InputError("the mesh is flat in z: a polycube needs height (--axis picks another)");
    const double dz = o.dz > 0.0 ? o.dz : height / 20.0;
    if (height / dz > 2000.0) throw geo::InputError("--dz is too small: more than 2000 planes");

    const CriticalStructure cs = critical_structure(ctx, mesh);
    st.saddles = cs.saddle_count();
    st.extrema = cs.extrema;
    std::vector<double> critical{mesh.positions[cs.minimum].z, mesh.positions[cs.maximum].z};
    for (std::uint32_t v : cs.saddles) critical.push_back(mesh.positions[v].z);
    std::vector<CuttingPlane> planes = cutting_planes(critical, dz, 1e-3 * height);
    st.inserted_planes = std::size_t(std::count_if(planes.begin(), planes.end(), [](auto& p) { return p.inserted; }));

    std::vector<double> zv;
    for (const auto& p : mesh.positions) zv.push_back(p.z);
    std::sort(zv.begin(), zv.end());
    double mean_edge = 0.0;
    for (const auto& t : mesh.triangles) mean_edge += glm::length(mesh.positions[t[1]] - mesh.positions[t[0]]);
    mean_edge /= double(mesh.face_count());

    SlicedMesh sliced;
    std::vector<glm::dvec3> carried;  // true_positions through the cuts
    std::vector<Contour> contours;
    PolycubeSurface surface;
    std::vector<std::vector<std::int32_t>> loop_contour;
    std::vector<PiecePair> pairs;
    bool matched = false;
    int round = 0, best_round = 0;
    std::size_t fewest = std::numeric_limits<std::size_t>::max();
    for (;;) {
        std::vector<double> plane_z;
        for (auto& p : planes) plane_z.push_back(p.z = clear_of_vertices(p.z, zv, 1e-7 * height, 0.05 * dz));
        carried = true_positions;
        sliced = slice_mesh(mesh, plane_z, &carried);
        contours = plane_contours(sliced, plane_z.size(), capped.original_faces);
        const ClosureCounts closed = close_contours(sliced.mesh, contours, o.k, mean_edge);
        check_time(stop_at);

        double excess = 0.0;
        const SlabPieces mesh_pieces = mesh_slab_pieces(sliced, contours, plane_z);
        const JoinedContours joined = joined_contours(mesh_pieces, contours, plane_z);
        Layers layers = stacked_regions(contours, plane_z, box, o.da, o.max_level, joined, excess, st.cells_carved);
        st.cells_filled = make_manifold(layers);
        st.cells_opened = layers.opened;
        check_time(stop_at);
        surface = polycube_surface(layers);

        loop_contour = match_loops(surface, contours, plane_z.size());
        SlabCheck check = check_slabs(mesh_pieces, contours, surface, loop_contour, plane_z);
        pairs = std::move(check.pairs);
        if (round == 0)
            for (std::size_t r = 0; r < std::min<std::size_t>(check.reasons.size(), 4); ++r)
                st.repair_note += (r ? "; " : "") + check.reasons[r];
        st.planes = plane_z.size();
        st.contours = contours.size();
        st.chains = closed.chains;
        st.closed_by_bezier = closed.bezier;
        st.closed_by_fallback = closed.fallback;
        st.closed_by_chord = closed.chord;
        st.closing_failed = closed.failed;
        st.quadtree_depth = layers.depth;
        st.mean_excess = plane_z.empty() ? 0.0 : excess / double(plane_z.size());
        st.pieces = check.mesh_pieces;
        matched = check.bad_slabs.empty() && check.bad_planes.empty();
        // Give up after 48 rounds, or 8 without fewer mismatches than the best so far.
        const std::size_t mismatches = check.bad_slabs.size() + check.bad_planes.size();
        if (mismatches < fewest) fewest = mismatches, best_round = round;
        if (matched || st.repair_planes >= o.max_repairs || ++round > 48 || round - best_round > 8) break;
        check_time(stop_at);
        // A plane whose section's regions came out with other loops than its contours (contours
        // closer than the deepest cells, a plane grazing a tip) moves within its gaps, up and down
        // by turns, to the nearby section with the fewest loops; the slabs beside it wait for the
        // next round.
        for (const std::size_t p : check.bad_planes) {
            const double lo = p == 0 ? box.min.z : plane_z[p - 1],
                         hi = p + 1 >= plane_z.size() ? box.max.z : plane_z[p + 1];
            const double z = plane_z[p], target = round % 2 ? z + 0.3 * (hi - z) : z - 0.3 * (z - lo);
            planes[p].z = target;
            for (double h : quiet_heights(mesh, z - 0.3 * (z - lo), z + 0.3 * (hi - z), target))
                if (std::abs(h - z) > 0.05 * (hi - lo)) {
                    planes[p].z = h;
                    break;
                }
            ++st.moved_planes;
            check.bad_slabs.erase(std::uint32_t(p));
            check.bad_slabs.erase(std::uint32_t(p + 1));
        }
        // A plane in every other slab that does not match (plane_placement.cpp says where).
        for (const std::uint32_t slab : check.bad_slabs) {
            if (st.repair_planes >= o.max_repairs) break;
            const double lo = slab == 0 ? box.min.z : plane_z[slab - 1];
            const double hi = slab >= plane_z.size() ? box.max.z : plane_z[slab];
            const std::vector<std::uint32_t>* handle = nullptr;
            for (std::size_t i = 0; i < mesh_pieces.triangles.size() && !handle; ++i)
                if (mesh_pieces.slab[i] == slab && !mesh_pieces.disk_like[i]) handle = &mesh_pieces.triangles[i];
            planes.push_back({repair_height(mesh, sliced, handle, lo, hi), true});
            ++st.repair_planes;
        }
        std::sort(planes.begin(), planes.end(), [](const CuttingPlane& a, const CuttingPlane& b) { return a.z < b.z; });
    }
    out.planes = planes;
    for (std::size_t p = 0; p < planes.size(); ++p) out.closed_contours.emplace_back();
    for (const auto& c : contours) out.closed_contours[c.plane].push_back(c.closed);

    // Validity of the polyhedron.
    const geo::MeshInfo pi = geo::analyze_topology(surface.mesh);
    st.polycube_faces = surface.faces;
    st.polycube_corners = surface.corners;
    st.polycube_triangles = surface.mesh.face_count();
    st.euler_characteristic = euler(pi);
    if (!pi.closed)
        st.invalid_reason = "not closed";
    else if (!pi.manifold)
        st.invalid_reason = "not manifold";
    else if (pi.components != 1)
        st.invalid_reason = std::to_string(pi.components) + " pieces";
    else if (!pi.oriented)
        st.invalid_reason = "not oriented";
    else if (st.euler_characteristic != 2 - 2 * (long long)st.genus)
        st.invalid_reason = "Euler characteristic " + std::to_string(st.euler_characteristic) + ", not 2 - 2g";
    st.polycube_valid = st.invalid_reason.empty();
    out.surface = surface.mesh;
    out.face_axis = surface.axis;
    out.hole.assign(surface.mesh.face_count(), 0);

    // Step 3: the map.
    if (o.map) {
        check_time(stop_at);
        if (!st.polycube_valid)
            st.map_note = "no map: the polycube is not valid (" + st.invalid_reason + ")";
        else if (!matched)
            st.map_note = "no map: some slab of the polycube does not join the contours the mesh's does";
        else {
            std::vector<std::int32_t> hole_of_face(mesh.face_count(), -1);
            for (std::size_t f = capped.original_faces; f < mesh.face_count(); ++f)  // caps end at their apex
                hole_of_face[f] = std::int32_t(mesh.triangles[f][volume < 0.0 ? 1 : 2] - capped.original_vertices);
            PolycubeMap m = map_pieces(ctx, sliced, contours, surface, loop_contour, pairs, hole_of_face, st);
            st.holes_marked = m.holes_marked;
            st.pieces_mapped = m.pieces_mapped;
            st.cut_mismatch = m.cut_mismatch;
            st.flips = m.disk_flips;
            st.boundary_snap = m.boundary_snap / box.diagonal();
            st.map_note = m.note;
            out.hole = m.surface_hole;
            st.hole_triangles = std::size_t(std::count(out.hole.begin(), out.hole.end(), 1));
            st.mapped = m.pieces_mapped == pairs.size();
            if (st.mapped) {
                SlicedMesh measured = sliced;  // the distortion of the mesh itself, not of its smoothed copy
                measured.mesh.positions = carried;
                PolycubeStatistics before;
                measure_map(measured, m, capped.original_faces, before);
                st.area_distortion_unsmoothed = before.area_distortion;
                st.angle_distortion_unsmoothed = before.angle_distortion;
                st.area_distortion_median_unsmoothed = before.area_distortion_median;
                st.angle_distortion_median_unsmoothed = before.angle_distortion_median;
                st.turned_chords_unsmoothed = before.turned_chords;
                st.smoothing_moves = smooth_map(sliced, carried, capped.original_faces, surface.mesh, surface.axis,
                                                m.image, m.image_axis, o.smoothing);
                out.mapped.assign(m.image.begin(), m.image.begin() + std::ptrdiff_t(input.vertex_count()));
                if (o.smoothing == 0) {  // nothing moved: the figures before are the figures
                    st.turned_chords = before.turned_chords;
                    st.area_distortion = before.area_distortion, st.angle_distortion = before.angle_distortion;
                    st.area_distortion_median = before.area_distortion_median;
                    st.angle_distortion_median = before.angle_distortion_median;
                } else {
                    measure_map(measured, m, capped.original_faces, st);
                }
            }
        }
    }
    st.max_level = o.max_level;
    st.slice_smoothing = o.slice_smoothing;
    st.seconds = std::chrono::duration<double>(Clock::now() - started).count();
    return out;
}

// The construction with the planes normal to axis a (0 x, 1 y, 2 z).
Polycube build_along(Context* ctx, const geo::Mesh& input, const PolycubeOptions& o, int a,
                     const std::optional<Clock::time_point>& stop_at) {
    Polycube out;
    if (a == 2) {
        out = build_along_z(ctx, input, o, stop_at);
    } else {
        // A cyclic permutation of the coordinates (it keeps the orientation) makes the axis z.
        const auto to_work = [a](glm::dvec3 p) { return glm::dvec3(p[(a + 1) % 3], p[(a + 2) % 3], p[a]); };
        const auto back = [a](glm::dvec3 w) {
            glm::dvec3 p;
            for (int k = 0; k < 3; ++k) p[(k + a + 1) % 3] = w[k];
            return p;
        };
        geo::Mesh work = input;
        for (auto& p : work.positions) p = to_work(p);
        out = build_along_z(ctx, work, o, stop_at);
        for (auto& p : out.surface.positions) p = back(p);
        for (auto& p : out.mapped) p = back(p);
        for (auto& x : out.face_axis) x = std::uint8_t(2 * ((x / 2 + a + 1) % 3) + x % 2);
    }
    out.stats.axis = std::uint8_t(a);
    return out;
}

}  // namespace

std::string failure_of(const PolycubeStatistics& s, bool map) {
    if (!s.polycube_valid) return "the polycube is not valid (" + s.invalid_reason + ")";
    if (map && !s.mapped) return "the map could not be built: " + s.map_note;
    return {};
}

Polycube build_polycube(Context* ctx, const geo::Mesh& input, const PolycubeOptions& o,
                        const std::function<void(const PolycubeStatistics& failed)>& retrying) {
    if (o.axis > 3) throw geo::InputError("the slicing axis must be x, y, z or auto");
    if (o.slice_smoothing > 1000) throw geo::InputError("the slice smoothing must be at most 1000 sweeps");
    if (!(o.retry_seconds >= 0.0)) throw geo::InputError("the retry time must be a number of seconds, 0 or more");
    // Per axis (auto: z, the paper's, then y and x), the options given, then the retries, none
    // started once the attempts took retry_seconds, and one still running then stopped. A refusal
    // of the mesh itself is not retried; all failing, the first attempt's result says why.
    std::vector<PolycubeOptions> tries{o};
    if (o.retry) {
        PolycubeOptions smoothed = o, deeper = o, both = o;
        smoothed.slice_smoothing = both.slice_smoothing = std::max<std::uint32_t>(o.slice_smoothing, 3);
        deeper.max_level = both.max_level = std::max<std::uint32_t>(o.max_level, 10);
        for (const PolycubeOptions& t : {smoothed, deeper, both})
            if (std::none_of(tries.begin(), tries.end(), [&](const PolycubeOptions& u) {
                    return u.max_level == t.max_level && u.slice_smoothing == t.slice_smoothing;
                }))
                tries.push_back(t);
    }
    std::vector<int> axes{2, 1, 0};
    if (o.axis < 3) axes = {int(o.axis)};
    Polycube first;
    std::size_t attempts = 0, axes_tried = 0;
    double seconds = 0.0, solve_seconds = 0.0;
    const std::size_t total = axes.size() * tries.size();
    bool cut_short = false;
    const auto begun = Clock::now();
    std::optional<Clock::time_point> stop_at;  // none past 1e9 s, which the clock's type may not hold
    if (o.retry_seconds < 1e9)
        stop_at = begun + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.retry_seconds));
    for (std::size_t k = 0; k < total && !cut_short; ++k) {
        const int a = axes[k / tries.size()];
        if (k % tries.size() == 0) ++axes_tried;
        Polycube p;
        try {
            p = build_along(ctx, input, tries[k % tries.size()], a, attempts > 0 ? stop_at : std::nullopt);
        } catch (const OutOfTime&) {
            ++attempts, cut_short = true;
            seconds = std::chrono::duration<double>(Clock::now() - begun).count();
            break;
        }
        seconds += p.stats.seconds, solve_seconds += p.stats.solve_seconds;
        p.stats.seconds = seconds, p.stats.solve_seconds = solve_seconds;
        p.stats.attempts = ++attempts, p.stats.axes_tried = axes_tried;
        if (failure_of(p.stats, o.map).empty()) return p;
        cut_short = attempts < total && seconds > o.retry_seconds;
        if (retrying && attempts < total && !cut_short) retrying(p.stats);
        if (attempts == 1) first = std::move(p);
    }
    first.stats.attempts = attempts, first.stats.axes_tried = axes_tried, first.stats.retries_cut_short = cut_short;
    first.stats.seconds = seconds, first.stats.solve_seconds = solve_seconds;
    return first;
}

}  // namespace gimg::passes
