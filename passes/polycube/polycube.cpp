// build_polycube: steps 1 to 3 in order, with the connectivity check that inserts a plane where a
// slab of the polycube does not join the same contours as the mesh's slab.
#include "polycube_parts.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/topology.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <functional>
#include <set>

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

double point_polyline_distance(glm::dvec2 p, const std::vector<glm::dvec2>& loop) {
    double best = 1e300;
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const glm::dvec2 a = loop[i], b = loop[(i + 1) % loop.size()];
        const glm::dvec2 ab = b - a;
        const double t = glm::dot(ab, ab) > 0 ? std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0) : 0.0;
        best = std::min(best, glm::length(p - (a + t * ab)));
    }
    return best;
}

struct Pieces {
    std::vector<std::vector<std::uint32_t>> triangles;
    std::vector<std::uint32_t> slab;
    std::vector<std::set<std::int32_t>> contours;
    std::vector<bool> disk_like;  // genus 0: chi = 2 - loops
};

// Components of triangles of the same slab joined across edges; their contour sets.
Pieces slab_pieces(const std::vector<glm::uvec3>& tris, const std::vector<std::uint32_t>& slab,
                   const std::function<std::int32_t(std::uint32_t)>& contour_of) {
    std::vector<std::uint32_t> parent(tris.size());
    std::iota(parent.begin(), parent.end(), 0u);
    const auto find = [&](std::uint32_t a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];
        return a;
    };
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edge;
    for (std::uint32_t f = 0; f < tris.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const auto [it, added] = edge.emplace(std::minmax(tris[f][k], tris[f][(k + 1) % 3]), f);
            if (!added && slab[it->second] == slab[f]) parent[find(f)] = find(it->second);
        }
    Pieces p;
    std::map<std::uint32_t, std::size_t> index;
    for (std::uint32_t f = 0; f < tris.size(); ++f) {
        const auto [it, added] = index.emplace(find(f), p.triangles.size());
        if (added) {
            p.triangles.emplace_back();
            p.slab.push_back(slab[f]);
            p.contours.emplace_back();
        }
        p.triangles[it->second].push_back(f);
        for (int k = 0; k < 3; ++k)
            if (const std::int32_t c = contour_of(tris[f][k]); c >= 0) p.contours[it->second].insert(c);
    }
    for (const auto& t : p.triangles) {
        std::set<std::uint32_t> vs;
        std::set<std::pair<std::uint32_t, std::uint32_t>> es;
        std::vector<glm::uvec3> local;
        for (std::uint32_t f : t) {
            local.push_back(tris[f]);
            for (int k = 0; k < 3; ++k) vs.insert(tris[f][k]), es.insert(std::minmax(tris[f][k], tris[f][(k + 1) % 3]));
        }
        const long long chi = (long long)vs.size() - (long long)es.size() + (long long)t.size();
        p.disk_like.push_back(chi == 2 - (long long)boundary_loops(local).size());
    }
    return p;
}

// Singular values of the linear map from triangle a to triangle b (each in its own plane).
std::pair<double, double> singular_values(const glm::dvec3 a[3], const glm::dvec3 b[3]) {
    const glm::dvec3 e1 = a[1] - a[0], e2 = a[2] - a[0], f1 = b[1] - b[0], f2 = b[2] - b[0];
    const double g11 = glm::dot(e1, e1), g12 = glm::dot(e1, e2), g22 = glm::dot(e2, e2);
    const double h11 = glm::dot(f1, f1), h12 = glm::dot(f1, f2), h22 = glm::dot(f2, f2);
    const double det_g = g11 * g22 - g12 * g12;
    if (!(det_g > 0.0)) return {0.0, 0.0};
    // G^-1 H: its eigenvalues are the squared singular values.
    const double m11 = (g22 * h11 - g12 * h12) / det_g, m12 = (g22 * h12 - g12 * h22) / det_g,
                 m21 = (g11 * h12 - g12 * h11) / det_g, m22 = (g11 * h22 - g12 * h12) / det_g;
    const double tr = m11 + m22, det = std::max(m11 * m22 - m12 * m21, 0.0);
    const double disc = std::sqrt(std::max(tr * tr / 4.0 - det, 0.0));
    return {std::sqrt(std::max(tr / 2.0 + disc, 0.0)), std::sqrt(std::max(tr / 2.0 - disc, 0.0))};
}

long long euler(const geo::MeshInfo& info) {
    long long chi = 0;
    for (const auto& c : info.component_info) chi += c.euler_characteristic;
    return chi;
}

const glm::dvec3 kAxis[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

// The construction with the planes normal to z.
Polycube build_along_z(Context* ctx, const geo::Mesh& input, const PolycubeOptions& o) {
    const auto started = std::chrono::steady_clock::now();
    if (!(o.dz >= 0.0) || !std::isfinite(o.dz)) throw geo::InputError("--dz must be a finite number >= 0");
    if (!(o.da > 0.0) || !std::isfinite(o.da)) throw geo::InputError("--da must be a finite number > 0");
    if (o.max_level > 10) throw geo::InputError("the quadtree level must be at most 10");
    if (o.k < 1) throw geo::InputError("--k must be at least 1");
    CappedMesh capped = cap_holes(input);
    geo::Mesh& mesh = capped.mesh;
    double volume = 0.0;
    for (const auto& t : mesh.triangles)
        volume += glm::dot(mesh.positions[t[0]], glm::cross(mesh.positions[t[1]], mesh.positions[t[2]]));
    if (volume < 0.0)  // the construction assumes outward faces
        for (auto& t : mesh.triangles) std::swap(t[1], t[2]);

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
    std::vector<Contour> contours;
    PolycubeSurface surface;
    std::vector<std::vector<std::int32_t>> loop_contour;
    std::vector<PiecePair> pairs;
    bool matched = false;
    for (;;) {
        std::vector<double> plane_z;
        for (auto& p : planes) plane_z.push_back(p.z = clear_of_vertices(p.z, zv, 1e-7 * height, 0.05 * dz));
        sliced = slice_mesh(mesh, plane_z);
        contours = plane_contours(sliced, plane_z.size(), capped.original_faces);
        const ClosureCounts closed = close_contours(sliced.mesh, contours, o.k, mean_edge);

        // Step 2-2: per plane, the rectilinear region of its closed contours, over one root.
        Rect root{{box.min.x, box.min.y}, {box.max.x, box.max.y}};
        for (const auto& c : contours)
            for (const auto& p : c.closed) root.min = glm::min(root.min, p), root.max = glm::max(root.max, p);
        std::vector<std::vector<std::vector<glm::dvec2>>> loops(plane_z.size());
        std::vector<std::vector<std::size_t>> contour_ids(plane_z.size());
        for (std::size_t c = 0; c < contours.size(); ++c) {
            loops[contours[c].plane].push_back(contours[c].closed);
            contour_ids[contours[c].plane].push_back(c);
        }
        std::vector<RectilinearRegion> regions;
        std::uint32_t depth = 0;
        double excess = 0.0;
        for (const auto& l : loops) {
            regions.push_back(rectilinear_region(l, root, o.da, o.max_level));
            depth = std::max(depth, regions.back().depth);
            excess += regions.back().excess();
        }
        Layers layers;
        layers.root = root;
        layers.depth = depth;
        layers.plane_z = plane_z;
        layers.bottom = box.min.z;
        layers.top = box.max.z;
        const int n = 1 << depth;
        for (const auto& r : regions) {
            std::vector<std::uint8_t> cells(std::size_t(n) * n);
            const int shift = int(depth - r.depth), rn = 1 << r.depth;
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x)
                    cells[std::size_t(y) * n + x] = r.cells[std::size_t(y >> shift) * rn + (x >> shift)];
            layers.cells.push_back(std::move(cells));
        }
        st.cells_filled = make_manifold(layers);
        surface = polycube_surface(layers);

        // Which contour each loop of the walls stands for: the nearest, one to one.
        loop_contour.assign(plane_z.size(), {});
        bool loops_match = true;
        for (std::size_t p = 0; p < plane_z.size(); ++p) {
            const auto& ls = surface.loops[p];
            loop_contour[p].assign(ls.size(), -1);
            std::vector<std::tuple<double, std::size_t, std::size_t>> cost;
            for (std::size_t l = 0; l < ls.size(); ++l) {
                std::vector<glm::dvec2> poly;
                for (std::uint32_t v : ls[l])
                    poly.push_back({surface.mesh.positions[v].x, surface.mesh.positions[v].y});
                for (std::size_t ci = 0; ci < contour_ids[p].size(); ++ci) {
                    const auto& cl = contours[contour_ids[p][ci]].closed;
                    const std::size_t step = std::max<std::size_t>(1, cl.size() / 48);
                    double d = 0.0;
                    std::size_t count = 0;
                    for (std::size_t i = 0; i < cl.size(); i += step, ++count)
                        d += point_polyline_distance(cl[i], poly);
                    cost.emplace_back(d / double(count), l, ci);
                }
            }
            std::sort(cost.begin(), cost.end());
            std::vector<bool> used(contour_ids[p].size(), false);
            for (const auto& [d, l, ci] : cost)
                if (loop_contour[p][l] < 0 && !used[ci])
                    loop_contour[p][l] = std::int32_t(contour_ids[p][ci]), used[ci] = true;
            if (ls.size() != contour_ids[p].size()) loops_match = false;
        }
        // The connectivity check: every slab piece of the mesh (genus 0) against the polycube's.
        std::vector<std::int32_t> contour_of(sliced.mesh.vertex_count(), -1);
        for (std::size_t c = 0; c < contours.size(); ++c)
            for (std::uint32_t v : contours[c].vertices) contour_of[v] = std::int32_t(c);
        std::vector<std::uint32_t> mesh_slab(sliced.mesh.face_count());
        for (std::size_t f = 0; f < mesh_slab.size(); ++f) {
            const auto& t = sliced.mesh.triangles[f];
            const double zc =
                (sliced.mesh.positions[t[0]].z + sliced.mesh.positions[t[1]].z + sliced.mesh.positions[t[2]].z) / 3.0;
            mesh_slab[f] = std::uint32_t(std::upper_bound(plane_z.begin(), plane_z.end(), zc) - plane_z.begin());
        }
        std::map<std::uint32_t, std::int32_t> surface_contour;
        for (std::size_t p = 0; p < plane_z.size(); ++p)
            for (std::size_t l = 0; l < surface.loops[p].size(); ++l)
                for (std::uint32_t v : surface.loops[p][l]) surface_contour[v] = loop_contour[p][l];
        const Pieces ms = slab_pieces(sliced.mesh.triangles, mesh_slab, [&](std::uint32_t v) { return contour_of[v]; });
        const Pieces ps = slab_pieces(surface.mesh.triangles, surface.slab, [&](std::uint32_t v) {
            const auto it = surface_contour.find(v);
            return it == surface_contour.end() ? -1 : it->second;
        });
        std::map<std::pair<std::uint32_t, std::set<std::int32_t>>, std::size_t> surface_piece;
        for (std::size_t i = 0; i < ps.triangles.size(); ++i) surface_piece[{ps.slab[i], ps.contours[i]}] = i;
        pairs.clear();
        std::set<std::uint32_t> bad_slabs;
        std::vector<std::size_t> mesh_pieces_in(plane_z.size() + 1, 0), surface_pieces_in(plane_z.size() + 1, 0);
        for (std::size_t i = 0; i < ps.triangles.size(); ++i) ++surface_pieces_in[ps.slab[i]];
        for (std::size_t i = 0; i < ms.triangles.size(); ++i) {
            ++mesh_pieces_in[ms.slab[i]];
            const auto it = surface_piece.find({ms.slab[i], ms.contours[i]});
            if (it == surface_piece.end() || !ms.disk_like[i]) {
                bad_slabs.insert(ms.slab[i]);
                continue;
            }
            pairs.push_back({ms.triangles[i], ps.triangles[it->second]});
        }
        for (std::size_t slab = 0; slab <= plane_z.size(); ++slab)
            if (mesh_pieces_in[slab] != surface_pieces_in[slab]) bad_slabs.insert(std::uint32_t(slab));
        for (std::size_t p = 0; p < plane_z.size(); ++p)  // a plane whose loops and contours differ in number
            if (surface.loops[p].size() != contour_ids[p].size())
                bad_slabs.insert(std::uint32_t(p)), bad_slabs.insert(std::uint32_t(p + 1));
        (void)loops_match;
        st.planes = plane_z.size();
        st.contours = contours.size();
        st.chains = closed.chains;
        st.closed_by_bezier = closed.bezier;
        st.closed_by_fallback = closed.fallback;
        st.closed_by_chord = closed.chord;
        st.closing_failed = closed.failed;
        st.quadtree_depth = depth;
        st.mean_excess = plane_z.empty() ? 0.0 : excess / double(plane_z.size());
        st.pieces = ms.triangles.size();
        matched = bad_slabs.empty();
        if (matched || st.repair_planes >= o.max_repairs) break;
        // A plane in the middle of every slab that does not match.
        for (const std::uint32_t slab : bad_slabs) {
            if (st.repair_planes >= o.max_repairs) break;
            const double lo = slab == 0 ? box.min.z : plane_z[slab - 1];
            const double hi = slab >= plane_z.size() ? box.max.z : plane_z[slab];
            planes.push_back({0.5 * (lo + hi), true});
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
        if (!st.polycube_valid)
            st.map_note = "no map: the polycube is not valid (" + st.invalid_reason + ")";
        else if (!matched)
            st.map_note = "no map: some slab of the polycube does not join the contours the mesh's does";
        else {
            const PolycubeMap m =
                map_pieces(ctx, sliced, contours, surface, loop_contour, pairs, capped.original_faces, st);
            st.pieces_mapped = m.pieces_mapped;
            st.cut_mismatch = m.cut_mismatch;
            st.flips = m.disk_flips;
            st.boundary_snap = m.boundary_snap / box.diagonal();
            st.map_note = m.note;
            out.hole = m.surface_hole;
            st.hole_triangles = std::size_t(std::count(out.hole.begin(), out.hole.end(), 1));
            st.mapped = m.pieces_mapped == pairs.size();
            if (st.mapped) {
                out.mapped.assign(m.image.begin(), m.image.begin() + std::ptrdiff_t(input.vertex_count()));
                // Flips and distortion over the real triangles of the sliced mesh.
                double area = 0.0, image_area = 0.0;
                std::vector<std::size_t> real;
                for (std::size_t f = 0; f < sliced.mesh.face_count(); ++f) {
                    if (sliced.source_face[f] >= capped.original_faces) continue;
                    const auto& t = sliced.mesh.triangles[f];
                    const glm::dvec3 n0 = glm::cross(sliced.mesh.positions[t[1]] - sliced.mesh.positions[t[0]],
                                                     sliced.mesh.positions[t[2]] - sliced.mesh.positions[t[0]]);
                    const glm::dvec3 n1 = glm::cross(m.image[t[1]] - m.image[t[0]], m.image[t[2]] - m.image[t[0]]);
                    const glm::dvec3 expected =
                        kAxis[m.image_axis[t[0]]] + kAxis[m.image_axis[t[1]]] + kAxis[m.image_axis[t[2]]];
                    if (!(glm::dot(n1, expected) > 0.0)) ++st.turned_chords;
                    area += 0.5 * glm::length(n0);
                    image_area += 0.5 * glm::length(n1);
                    real.push_back(f);
                }
                const double scale = image_area > 0 ? std::sqrt(area / image_area) : 1.0;
                double wsum = 0.0;
                for (std::size_t f : real) {
                    const auto& t = sliced.mesh.triangles[f];
                    const glm::dvec3 a[3] = {sliced.mesh.positions[t[0]], sliced.mesh.positions[t[1]],
                                             sliced.mesh.positions[t[2]]};
                    const glm::dvec3 b[3] = {scale * m.image[t[0]], scale * m.image[t[1]], scale * m.image[t[2]]};
                    const auto [s1, s2] = singular_values(a, b);
                    const double w = 0.5 * glm::length(glm::cross(a[1] - a[0], a[2] - a[0]));
                    if (!(s2 > 1e-12) || w <= 0.0) continue;
                    st.area_distortion += w * 0.5 * (s1 * s2 + 1.0 / (s1 * s2));
                    st.angle_distortion += w * 0.5 * (s1 / s2 + s2 / s1);
                    wsum += w;
                }
                if (wsum > 0) st.area_distortion /= wsum, st.angle_distortion /= wsum;
            } else if (st.map_note.empty()) {
                st.map_note = std::to_string(pairs.size() - m.pieces_mapped) + " of " + std::to_string(pairs.size()) +
                              " pieces could not be cut to matching disks";
            }
        }
    }
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return out;
}

}  // namespace

Polycube build_polycube(Context* ctx, const geo::Mesh& input, const PolycubeOptions& o) {
    if (o.axis > 2) throw geo::InputError("the slicing axis must be x, y or z");
    if (o.axis == 2) return build_along_z(ctx, input, o);
    // A cyclic permutation of the coordinates (it keeps the orientation) makes the axis z.
    const int a = o.axis;
    const auto to_work = [a](glm::dvec3 p) { return glm::dvec3(p[(a + 1) % 3], p[(a + 2) % 3], p[a]); };
    const auto back = [a](glm::dvec3 w) {
        glm::dvec3 p;
        for (int k = 0; k < 3; ++k) p[(k + a + 1) % 3] = w[k];
        return p;
    };
    geo::Mesh work = input;
    for (auto& p : work.positions) p = to_work(p);
    Polycube out = build_along_z(ctx, work, o);
    for (auto& p : out.surface.positions) p = back(p);
    for (auto& p : out.mapped) p = back(p);
    for (auto& x : out.face_axis) x = std::uint8_t(2 * ((x / 2 + a + 1) % 3) + x % 2);
    return out;
}

}  // namespace gimg::passes
