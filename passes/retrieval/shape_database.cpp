// The database: PCA of the features (the thesis, 5.3), the search with the pose variants, the file.
#include "gimg/passes/retrieval.h"

#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/parallel_for.h"
#include "json_problem.h"

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

namespace gimg::passes {

namespace {

// The query in the four poses PCA's free signs give, on the reduced R x R image (R even): as
// aligned; turned end over end (y -> -y, z -> -z: rows reversed, theta -> -theta); turned half way
// about the axis (theta -> theta + pi); both.
std::vector<std::vector<float>> poses(const std::vector<float>& f, std::uint32_t r, PoseHandling pose) {
    std::vector<std::vector<float>> out{f};
    if (pose == PoseHandling::AsAligned) return out;
    auto make = [&](bool over, bool half) {
        std::vector<float> g(f.size());
        for (std::uint32_t v = 0; v < r; ++v)
            for (std::uint32_t u = 0; u < r; ++u) {
                std::uint32_t su = over ? r - 1 - u : u, sv = over ? r - 1 - v : v;
                if (half) su = (su + r / 2) % r;
                g[std::size_t(v) * r + u] = f[std::size_t(sv) * r + su];
            }
        return g;
    };
    out.push_back(make(true, false));
    out.push_back(make(false, true));
    out.push_back(make(true, true));
    return out;
}

std::size_t descriptor_size(const RetrievalOptions& o) {
    if (o.descriptor == RetrievalDescriptor::Panorama) return 6 * (kPanoramaBand + 1) * (kPanoramaBand + 1);
    const std::size_t r = o.reduced;
    const std::size_t one = o.cylinders * (o.descriptor == RetrievalDescriptor::Image ? r * r : r * (r / 2 + 1));
    return o.descriptor == RetrievalDescriptor::Spectrum2DSlope ? 2 * one : one;
}

const char* descriptor_name(RetrievalDescriptor d) {
    return d == RetrievalDescriptor::Image           ? "image"
           : d == RetrievalDescriptor::ThetaSpectrum ? "theta_spectrum"
           : d == RetrievalDescriptor::Spectrum2D    ? "spectrum_2d"
           : d == RetrievalDescriptor::Panorama      ? "panorama"
                                                     : "spectrum_2d_slope";
}

std::vector<float> spectra(const RetrievalOptions& options, const std::vector<float>& image);

// cos and sin of 2 pi k m / n for m = 0 .. n - 1 (rows) and k = 0 .. kmax (columns): the DFT's turns
// as matrices, so each transform is a matrix product.
struct Turns {
    Eigen::MatrixXd cosine, sine;
};
Turns turns(std::size_t n, std::size_t kmax) {
    Turns t{Eigen::MatrixXd(n, kmax + 1), Eigen::MatrixXd(n, kmax + 1)};
    for (std::size_t m = 0; m < n; ++m)
        for (std::size_t k = 0; k <= kmax; ++k) {
            const double a = 2.0 * 3.14159265358979323846 * double(k * m % n) / double(n);
            t.cosine(Eigen::Index(m), Eigen::Index(k)) = std::cos(a);
            t.sine(Eigen::Index(m), Eigen::Index(k)) = std::sin(a);
        }
    return t;
}

// A complex matrix as its two parts.
struct Complex {
    Eigen::MatrixXd re, im;
};

// sum_m x(m, j) cos(2 pi k m / n) and the same with sin, over the n rows of x, for every column j
// and the turns' frequencies k ((kmax + 1) x columns each). For n even by the transform's symmetry,
// cos(2 pi k (n - m) / n) = cos(2 pi k m / n) and sin(...) = -sin(2 pi k m / n): the sums x_m +
// x_{n - m} meet the cosines and the differences the sines, half the products.
struct CosSin {
    Eigen::MatrixXd c, s;
};
CosSin cos_sin_sums(const Eigen::MatrixXd& x, const Turns& t) {
    const Eigen::Index n = x.rows(), half = n / 2;
    if (n % 2 != 0) return {t.cosine.transpose() * x, t.sine.transpose() * x};
    Eigen::MatrixXd sum(half + 1, x.cols());
    sum.row(0) = x.row(0);
    sum.row(half) = x.row(half);
    sum.middleRows(1, half - 1) = x.middleRows(1, half - 1) + x.bottomRows(half - 1).colwise().reverse();
    const Eigen::MatrixXd difference = x.middleRows(1, half - 1) - x.bottomRows(half - 1).colwise().reverse();
    return {t.cosine.topRows(half + 1).transpose() * sum, t.sine.middleRows(1, half - 1).transpose() * difference};
}

// Per row of a w-wide image of `rows` rows, its DFT over the row (theta) at the turns' frequencies:
// rows x (kmax + 1).
template <typename T>
Complex theta_dft(const T* image, std::size_t w, std::size_t rows, const Turns& theta) {
    // The image's rows are the columns of a column-major w x rows map.
    using Columns = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const Eigen::MatrixXd x =
        Eigen::Map<const Columns>(image, Eigen::Index(w), Eigen::Index(rows)).template cast<double>();
    const CosSin t = cos_sin_sums(x, theta);
    return {t.c.transpose(), -t.s.transpose()};
}

// The DFT over height (the h rows of `rows`) at the turns' frequencies kh: `up` with e^{-i 2 pi kh
// y / h}, `down` with its conjugate (the frequency -kh): (kmax + 1) x rows' columns each.
void height_dft(const Complex& rows, const Turns& height, Complex* up, Complex* down) {
    const CosSin r = cos_sin_sums(rows.re, height), i = cos_sin_sums(rows.im, height);
    up->re = r.c + i.s, up->im = i.c - r.s;
    if (down) down->re = r.c - i.s, down->im = i.c + r.s;
}

// |F(kh, kt)| of a W x H image for kh, kt in 0 .. band (the turns), each averaged with |F(-kh, kt)|
// so that the image turned end over end (or mirrored in theta) has the same values; kh outer.
std::vector<double> low_band(const double* image, const Turns& theta, const Turns& height) {
    const auto w = std::size_t(theta.cosine.rows()), h = std::size_t(height.cosine.rows());
    Complex up, down;
    height_dft(theta_dft(image, w, h, theta), height, &up, &down);
    const Eigen::MatrixXd both = 0.5 * ((up.re.array().square() + up.im.array().square()).sqrt() +
                                        (down.re.array().square() + down.im.array().square()).sqrt());
    std::vector<double> out(std::size_t(both.size()));
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(out.data(), both.rows(),
                                                                                       both.cols()) = both;
    return out;
}

// Panorama's descriptor of its three images: per image the distance channel and the orientation
// channel, |cos| between the wall's ray and the surface, from the image's own slope (radius 1 is
// the image's wall, its height 2 radii), each channel's low band scaled to sum 1.
std::vector<float> panorama_descriptor(const std::vector<float>& images) {
    constexpr std::uint32_t w = kPanoramaWidth, h = kPanoramaHeight;
    constexpr double kStepTheta = 2.0 * 3.14159265358979323846 / w, kStepHeight = 2.0 / h;
    static const Turns theta = turns(w, kPanoramaBand), height = turns(h, kPanoramaBand);
    std::vector<float> out;
    for (std::size_t c = 0; c < 3; ++c) {
        const float* d = images.data() + c * w * h;
        std::vector<double> distance(std::size_t(w) * h), facing(std::size_t(w) * h, 0.0);
        for (std::size_t i = 0; i < distance.size(); ++i) distance[i] = d[i];
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) {
                const double r = distance[std::size_t(y) * w + x];
                if (!(r > 0.0)) continue;
                const auto at = [&](std::uint32_t xx, std::uint32_t yy) { return distance[std::size_t(yy) * w + xx]; };
                const double along_theta =
                    (at((x + 1) % w, y) - at((x + w - 1) % w, y)) / (2.0 * kStepTheta * std::max(r, 1e-3));
                const std::uint32_t y0 = y > 0 ? y - 1 : 0, y1 = std::min(y + 1, h - 1);
                const double along_height = (at(x, y1) - at(x, y0)) / (double(y1 - y0) * kStepHeight);
                facing[std::size_t(y) * w + x] =
                    1.0 / std::sqrt(1.0 + along_theta * along_theta + along_height * along_height);
            }
        for (const std::vector<double>* channel : {&distance, &facing}) {
            const std::vector<double> band = low_band(channel->data(), theta, height);
            double sum = 0.0;
            for (double v : band) sum += v;
            for (double v : band) out.push_back(float(sum > 0.0 ? v / sum : 0.0));
        }
    }
    return out;
}

}  // namespace

std::size_t feature_size(const RetrievalOptions& options) {
    if (options.descriptor == RetrievalDescriptor::Panorama) return 3 * std::size_t(kPanoramaWidth) * kPanoramaHeight;
    return std::size_t(options.cylinders) * options.reduced * options.reduced;
}

std::vector<float> describe_feature(const RetrievalOptions& options, const std::vector<float>& image) {
    const std::size_t r = options.reduced;
    if (image.size() != feature_size(options))
        throw geo::InputError("retrieval: the feature does not match the database's size");
    if (options.descriptor == RetrievalDescriptor::Panorama) return panorama_descriptor(image);
    if (options.descriptor == RetrievalDescriptor::Image) return image;
    if (options.descriptor != RetrievalDescriptor::Spectrum2DSlope) return spectra(options, image);
    // The slope: central differences, circular in theta, one-sided at the top and bottom rows.
    std::vector<float> slope(image.size());
    for (std::size_t c = 0; c < options.cylinders; ++c)
        for (std::size_t v = 0; v < r; ++v)
            for (std::size_t u = 0; u < r; ++u) {
                auto at = [&](std::size_t uu, std::size_t vv) { return image[(c * r + vv) * r + uu]; };
                const float du = at((u + 1) % r, v) - at((u + r - 1) % r, v);
                const float dv = at(u, std::min(v + 1, r - 1)) - at(u, v > 0 ? v - 1 : 0);
                slope[(c * r + v) * r + u] = std::sqrt(du * du + dv * dv);
            }
    RetrievalOptions plain = options;
    plain.descriptor = RetrievalDescriptor::Spectrum2D;
    std::vector<float> out = spectra(plain, image), second = spectra(plain, slope);
    for (std::vector<float>* half : {&out, &second}) {
        double length = 0.0;
        for (float f : *half) length += double(f) * f;
        length = std::sqrt(length);
        if (length > 0.0)
            for (float& f : *half) f = float(f / length);
    }
    out.insert(out.end(), second.begin(), second.end());
    return out;
}

namespace {

// ThetaSpectrum or Spectrum2D of a reduced image.
std::vector<float> spectra(const RetrievalOptions& options, const std::vector<float>& image) {
    const std::size_t r = options.reduced;
    // Per row (the cylinders' rows one after another), the DFT over theta, k = 0 .. r / 2.
    const Complex rows = theta_dft(image.data(), r, options.cylinders * r, turns(r, r / 2));
    std::vector<float> out;
    const auto magnitude = [&](const Complex& z) {  // row after row
        for (Eigen::Index i = 0; i < z.re.rows(); ++i)
            for (Eigen::Index j = 0; j < z.re.cols(); ++j) out.push_back(float(std::hypot(z.re(i, j), z.im(i, j))));
    };
    if (options.descriptor == RetrievalDescriptor::ThetaSpectrum) {
        magnitude(rows);
        return out;
    }
    // Spectrum2D: each cylinder's row spectra transformed again over height, l = 0 .. r - 1.
    const Turns height = turns(r, r - 1);
    for (std::size_t c = 0; c < options.cylinders; ++c) {
        const auto block = [&](const Eigen::MatrixXd& m) {
            return Eigen::MatrixXd(m.middleRows(Eigen::Index(c * r), Eigen::Index(r)));
        };
        Complex z;
        height_dft({block(rows.re), block(rows.im)}, height, &z, nullptr);
        magnitude(z);
    }
    return out;
}

}  // namespace

std::vector<std::vector<float>> describe_features(const RetrievalOptions& options,
                                                  const std::vector<std::vector<float>>& features) {
    for (const auto& f : features)
        if (f.size() != feature_size(options)) throw geo::InputError("retrieval: features of different sizes");
    std::vector<std::vector<float>> out(features.size());
    geo::parallel_for_chunks(features.size(), 1, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) out[i] = describe_feature(options, features[i]);
    });
    return out;
}

ShapeDatabase panorama_database(std::vector<std::vector<float>> descriptors, std::vector<std::string> paths,
                                std::vector<std::string> labels) {
    const std::size_t n = descriptors.size();
    if (n < 2) throw geo::InputError("retrieval: a database needs at least 2 models, got " + std::to_string(n));
    if (paths.size() != n || labels.size() != n) throw geo::InputError("retrieval: paths and labels per model");
    ShapeDatabase db;
    db.options.descriptor = RetrievalDescriptor::Panorama;
    db.options.cylinders = 3;
    db.k = std::uint32_t(descriptor_size(db.options));
    db.variance_kept = 1.0;
    for (const auto& d : descriptors)
        if (d.size() != db.k) throw geo::InputError("retrieval: a descriptor of another size");
    db.coefficients = std::move(descriptors);
    db.paths = std::move(paths);
    db.labels = std::move(labels);
    return db;
}

ShapeDatabase build_shape_database(const std::vector<std::vector<float>>& features, std::vector<std::string> paths,
                                   std::vector<std::string> labels, const RetrievalOptions& options) {
    const std::size_t n = features.size(), d = descriptor_size(options);
    if (n < 2) throw geo::InputError("retrieval: a database needs at least 2 models, got " + std::to_string(n));
    if (paths.size() != n || labels.size() != n) throw geo::InputError("retrieval: paths and labels per model");
    if (!(options.variance > 0.0 && options.variance <= 1.0))
        throw geo::InputError("retrieval: the variance share must be in (0, 1]");
    if (options.descriptor == RetrievalDescriptor::Panorama)
        return panorama_database(describe_features(options, features), std::move(paths), std::move(labels));
    Eigen::MatrixXd x(n, d);
    for (std::size_t i = 0; i < n; ++i) {
        if (features[i].size() != feature_size(options))
            throw geo::InputError("retrieval: features of different sizes");
        const std::vector<float> f = describe_feature(options, features[i]);
        for (std::size_t j = 0; j < d; ++j) x(Eigen::Index(i), Eigen::Index(j)) = f[j];
    }
    const Eigen::RowVectorXd mean = x.colwise().mean();
    x.rowwise() -= mean;
    const Eigen::BDCSVD<Eigen::MatrixXd> svd(x, Eigen::ComputeThinV);
    const Eigen::VectorXd variances = svd.singularValues().array().square();
    const double total = variances.sum();
    ShapeDatabase db;
    db.options = options;
    double kept = 0.0;
    while (db.k < variances.size() && (db.k == 0 || kept < options.variance * total)) kept += variances[db.k++];
    db.variance_kept = total > 0.0 ? kept / total : 1.0;
    const Eigen::MatrixXd loadings = svd.matrixV().leftCols(db.k);
    db.mean.assign(mean.data(), mean.data() + d);
    db.loadings.assign(loadings.data(), loadings.data() + loadings.size());  // column-major
    const Eigen::MatrixXd coefficients = x * loadings;
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<float> c(db.k);
        for (std::uint32_t j = 0; j < db.k; ++j) c[j] = float(coefficients(Eigen::Index(i), Eigen::Index(j)));
        db.coefficients.push_back(std::move(c));
    }
    db.paths = std::move(paths);
    db.labels = std::move(labels);
    return db;
}

std::vector<float> project_feature(const ShapeDatabase& db, const std::vector<float>& image) {
    const std::vector<float> feature = describe_feature(db.options, image);
    if (db.options.descriptor == RetrievalDescriptor::Panorama) return feature;
    const std::size_t d = db.mean.size();
    if (feature.size() != d) throw geo::InputError("retrieval: the feature does not match the database's size");
    std::vector<float> c(db.k);
    for (std::uint32_t j = 0; j < db.k; ++j) {
        double s = 0.0;
        const float* column = db.loadings.data() + std::size_t(j) * d;
        for (std::size_t i = 0; i < d; ++i) s += (double(feature[i]) - double(db.mean[i])) * double(column[i]);
        c[j] = float(s);
    }
    return c;
}

std::vector<ShapeMatch> search_shapes(const ShapeDatabase& db, const std::vector<float>& feature, PoseHandling pose,
                                      std::size_t exclude) {
    std::vector<ShapeMatch> out;
    if (db.options.descriptor == RetrievalDescriptor::Panorama) {  // invariant already: L1, one pose
        const std::vector<float> q = project_feature(db, feature);
        for (std::size_t m = 0; m < db.size(); ++m) {
            if (m == exclude) continue;
            // Eight running sums, so the loop vectorises without reordering one sum.
            const float* c = db.coefficients[m].data();
            float part[8] = {};
            std::uint32_t j = 0;
            for (; j + 8 <= db.k; j += 8)
                for (int l = 0; l < 8; ++l) part[l] += std::abs(q[j + l] - c[j + l]);
            double s = 0.0;
            for (float p : part) s += p;
            for (; j < db.k; ++j) s += std::abs(q[j] - c[j]);
            out.push_back({m, s});
        }
        std::stable_sort(out.begin(), out.end(),
                         [](const ShapeMatch& a, const ShapeMatch& b) { return a.distance < b.distance; });
        return out;
    }
    std::vector<std::vector<float>> queries;
    const PoseHandling used = db.options.cylinders == 1 ? pose : PoseHandling::AsAligned;
    for (const auto& variant : poses(feature, db.options.reduced, used))
        queries.push_back(project_feature(db, variant));
    for (std::size_t m = 0; m < db.size(); ++m) {
        if (m == exclude) continue;
        double best = std::numeric_limits<double>::infinity();
        for (const auto& q : queries) {
            double s = 0.0;
            for (std::uint32_t j = 0; j < db.k; ++j) {
                const double e = double(q[j]) - double(db.coefficients[m][j]);
                s += e * e;
            }
            best = std::min(best, s);
        }
        out.push_back({m, best});
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const ShapeMatch& a, const ShapeMatch& b) { return a.distance < b.distance; });
    return out;
}

void write_shape_database(const std::filesystem::path& path, const ShapeDatabase& db) {
    nlohmann::json j;
    j["format"] = "gimg shape database";
    j["version"] = 1;
    j["size"] = db.options.size;
    j["reduced"] = db.options.reduced;
    j["variance"] = db.options.variance;
    j["descriptor"] = descriptor_name(db.options.descriptor);
    j["cylinders"] = db.options.cylinders;
    j["k"] = db.k;
    j["variance_kept"] = db.variance_kept;
    j["mean"] = db.mean;
    j["loadings"] = db.loadings;
    j["models"] = nlohmann::json::array();
    for (std::size_t i = 0; i < db.size(); ++i)
        j["models"].push_back({{"path", db.paths[i]}, {"label", db.labels[i]}, {"coefficients", db.coefficients[i]}});
    geo::write_file_atomically(path, j.dump() + "\n");
}

ShapeDatabase read_shape_database(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw geo::InputError("cannot read " + path.string() + ": no such file");
    ShapeDatabase db;
    try {
        const nlohmann::json j = nlohmann::json::parse(in);
        if (j.value("format", std::string()) != "gimg shape database")
            throw geo::InputError(path.string() + " is not a gimg shape database (gimg index writes one)");
        db.options.size = j.at("size").get<std::uint32_t>();
        db.options.reduced = j.at("reduced").get<std::uint32_t>();
        db.options.variance = j.at("variance").get<double>();
        const std::string descriptor = j.value("descriptor", std::string("image"));
        if (descriptor != "image" && descriptor != "theta_spectrum" && descriptor != "spectrum_2d" &&
            descriptor != "spectrum_2d_slope" && descriptor != "panorama")
            throw geo::InputError(path.string() + ": unknown descriptor \"" + descriptor + "\"");
        db.options.descriptor = descriptor == "image"            ? RetrievalDescriptor::Image
                                : descriptor == "theta_spectrum" ? RetrievalDescriptor::ThetaSpectrum
                                : descriptor == "spectrum_2d"    ? RetrievalDescriptor::Spectrum2D
                                : descriptor == "panorama"       ? RetrievalDescriptor::Panorama
                                                                 : RetrievalDescriptor::Spectrum2DSlope;
        db.options.cylinders = j.value("cylinders", 1u);
        if (db.options.cylinders != 1 && db.options.cylinders != 3)
            throw geo::InputError(path.string() + ": cylinders must be 1 or 3");
        db.k = j.at("k").get<std::uint32_t>();
        db.variance_kept = j.at("variance_kept").get<double>();
        db.mean = j.at("mean").get<std::vector<float>>();
        db.loadings = j.at("loadings").get<std::vector<float>>();
        for (const auto& m : j.at("models")) {
            db.paths.push_back(m.at("path").get<std::string>());
            db.labels.push_back(m.at("label").get<std::string>());
            db.coefficients.push_back(m.at("coefficients").get<std::vector<float>>());
        }
    } catch (const nlohmann::json::exception& e) {
        throw geo::InputError(path.string() + " is not a gimg shape database: " + detail::json_problem(e));
    }
    const std::size_t d = descriptor_size(db.options);
    const bool panorama = db.options.descriptor == RetrievalDescriptor::Panorama;
    bool ok = db.options.reduced > 0 && db.options.reduced % 2 == 0 && db.options.size % db.options.reduced == 0 &&
              db.size() >= 2 &&
              (panorama ? db.mean.empty() && db.loadings.empty() && db.k == d
                        : db.mean.size() == d && db.loadings.size() == d * db.k);
    for (const auto& c : db.coefficients) ok = ok && c.size() == db.k;
    if (!ok) throw geo::InputError(path.string() + ": its arrays do not match its sizes");
    return db;
}

RetrievalScores score_ranking(const std::vector<std::string>& ranked, const std::string& label, std::size_t relevant) {
    RetrievalScores s;
    if (relevant == 0 || ranked.empty()) return s;
    s.nearest_neighbour = ranked[0] == label ? 1.0 : 0.0;
    std::size_t found = 0, in_first = 0, in_second = 0;
    double dcg = 0.0, precision_sum = 0.0;
    for (std::size_t i = 0; i < ranked.size(); ++i) {
        if (ranked[i] != label) continue;
        ++found;
        if (i < relevant) ++in_first;
        if (i < 2 * relevant) ++in_second;
        dcg += i == 0 ? 1.0 : 1.0 / std::log2(double(i + 1));
        precision_sum += double(found) / double(i + 1);
    }
    double ideal = 1.0;
    for (std::size_t i = 1; i < relevant; ++i) ideal += 1.0 / std::log2(double(i + 1));
    s.first_tier = double(in_first) / double(relevant);
    s.second_tier = double(in_second) / double(relevant);
    s.dcg = dcg / ideal;
    s.average_precision = precision_sum / double(relevant);
    return s;
}

}  // namespace gimg::passes
