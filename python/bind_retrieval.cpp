// The Python module: retrieval from cylindrical images: index, search, leave-one-out scores.
#include "module_support.h"

#include "gimg/geometry/error.h"
#include "gimg/passes/retrieval.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>

namespace gimg::python {

void bind_retrieval(py::module_& m) {
    py::class_<passes::ShapeDatabase>(m, "ShapeDatabase", "A retrieval index (gimg index)")
        .def_property_readonly("size", &passes::ShapeDatabase::size)
        .def_readonly("k", &passes::ShapeDatabase::k)
        .def_readonly("variance_kept", &passes::ShapeDatabase::variance_kept)
        .def_readonly("labels", &passes::ShapeDatabase::labels)
        .def("save",
             [](const passes::ShapeDatabase& db, const std::string& path) { passes::write_shape_database(path, db); })
        .def(
            "search",
            [](const passes::ShapeDatabase& db, Device& device, const Positions& positions, const Faces& faces,
               std::size_t k, const std::string& pose) {
                if (pose != "best-of-four" && pose != "aligned") throw geo::InputError("pose: best-of-four or aligned");
                const geo::Mesh mesh = to_mesh(positions, faces);
                std::vector<passes::ShapeMatch> matches;
                {
                    py::gil_scoped_release release;
                    const auto feature = passes::cylinder_features(device.context(), {mesh}, db.options).front();
                    matches = passes::search_shapes(
                        db, feature,
                        pose == "aligned" ? passes::PoseHandling::AsAligned : passes::PoseHandling::BestOfFour);
                }
                py::list out;
                for (std::size_t i = 0; i < matches.size() && i < k; ++i)
                    out.append(py::make_tuple(matches[i].model, matches[i].distance));
                return out;
            },
            py::arg("device"), py::arg("positions"), py::arg("faces"), py::arg("k") = 10,
            py::arg("pose") = "best-of-four",
            "The k models most like the mesh (gimg search): a list of (model index, distance), nearest first")
        .def(
            "evaluate",
            [](const passes::ShapeDatabase& db, Device& device, const py::list& meshes, const std::string& pose) {
                if (pose != "best-of-four" && pose != "aligned") throw geo::InputError("pose: best-of-four or aligned");
                const std::vector<geo::Mesh> ms = to_meshes(meshes);
                if (ms.size() != db.size()) throw geo::InputError("evaluate: the database's meshes, in its order");
                std::map<std::string, std::size_t> class_size;
                for (const auto& l : db.labels) ++class_size[l];
                passes::RetrievalScores total;
                std::size_t queries = 0;
                {
                    py::gil_scoped_release release;
                    const auto features = passes::cylinder_features(device.context(), ms, db.options);
                    for (std::size_t q = 0; q < ms.size(); ++q) {
                        const std::size_t relevant = class_size[db.labels[q]] - 1;
                        if (relevant == 0) continue;  // nothing to find
                        std::vector<std::string> ranked;
                        for (const auto& match : passes::search_shapes(
                                 db, features[q],
                                 pose == "aligned" ? passes::PoseHandling::AsAligned : passes::PoseHandling::BestOfFour,
                                 q))
                            ranked.push_back(db.labels[match.model]);
                        const passes::RetrievalScores r = passes::score_ranking(ranked, db.labels[q], relevant);
                        total.nearest_neighbour += r.nearest_neighbour, total.first_tier += r.first_tier;
                        total.second_tier += r.second_tier, total.dcg += r.dcg;
                        total.average_precision += r.average_precision;
                        ++queries;
                    }
                }
                if (queries == 0) throw geo::InputError("evaluate: no class has two models");
                py::dict d;
                d["nn"] = total.nearest_neighbour / double(queries),
                d["first_tier"] = total.first_tier / double(queries);
                d["second_tier"] = total.second_tier / double(queries), d["dcg"] = total.dcg / double(queries);
                d["map"] = total.average_precision / double(queries), d["queries"] = queries;
                return d;
            },
            py::arg("device"), py::arg("meshes"), py::arg("pose") = "best-of-four",
            "Leave-one-out scores over the database's own models (gimg eval): a dict with nn, first_tier, "
            "second_tier, dcg, map (means over the queries) and queries");
    m.def(
        "load_database", [](const std::string& path) { return passes::read_shape_database(path); }, py::arg("path"),
        "A database written by gimg index or ShapeDatabase.save");
    m.def(
        "index",
        [](Device& device, const py::list& meshes, std::vector<std::string> labels, std::uint32_t size,
           std::uint32_t reduced, double variance, const std::string& descriptor) {
            const std::vector<geo::Mesh> ms = to_meshes(meshes);
            if (!labels.empty() && labels.size() != ms.size()) throw geo::InputError("labels: one per mesh, or none");
            labels.resize(ms.size());
            std::vector<std::string> names(ms.size());
            for (std::size_t i = 0; i < ms.size(); ++i) names[i] = "model " + std::to_string(i);
            passes::RetrievalOptions o;
            o.size = size, o.reduced = reduced, o.variance = variance;
            if (descriptor == "panorama")
                o.descriptor = passes::RetrievalDescriptor::Panorama;
            else if (descriptor == "spectrum2d-slope")
                o.descriptor = passes::RetrievalDescriptor::Spectrum2DSlope;
            else if (descriptor != "image")
                throw geo::InputError("descriptor: image, spectrum2d-slope or panorama, not \"" + descriptor + "\"");
            if (o.reduced % 2 != 0 || o.size % o.reduced != 0)
                throw geo::InputError("size must be a multiple of reduced, and reduced even");
            py::gil_scoped_release release;
            return passes::build_shape_database(passes::cylinder_features(device.context(), ms, o), names, labels, o);
        },
        py::arg("device"), py::arg("meshes"), py::arg("labels") = std::vector<std::string>{}, py::arg("size") = 144,
        py::arg("reduced") = 48, py::arg("variance") = 0.95, py::arg("descriptor") = "image",
        "A retrieval index of a list of (positions, faces) (gimg index): descriptor image (the thesis's, "
        "default), spectrum2d-slope or panorama (the best; size, reduced and variance do not apply). A "
        "ShapeDatabase");
}

}  // namespace gimg::python
