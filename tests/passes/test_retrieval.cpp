// Retrieval from cylindrical images: the reduction, the PCA, the search's pose handling and the
// benchmark measures.
#include "gpu_test.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/shapes.h"
#include "gimg/passes/retrieval.h"

#include <glm/ext/matrix_transform.hpp>

#include <cmath>
#include <filesystem>
#include <random>

using namespace gimg;
namespace gp = gimg::passes;

TEST(Retrieval, ReductionKeepsConstantsAndTurnsWithTheImage) {
    gp::CylinderImage image(144, 144);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> d(-0.9f, 0.9f);
    for (std::size_t i = 0; i < image.distance.size(); ++i) image.covered[i] = 1, image.distance[i] = 0.5f;
    for (float v : gp::reduce_cylinder_image(image, 48)) ASSERT_NEAR(v, 0.5f, 1e-6f);
    for (std::size_t i = 0; i < image.distance.size(); ++i) image.covered[i] = i % 7 != 0, image.distance[i] = d(rng);
    // Turning the model about the axis by 3 input columns turns the feature by one column (circular).
    gp::CylinderImage turned(144, 144);
    for (std::uint32_t v = 0; v < 144; ++v)
        for (std::uint32_t u = 0; u < 144; ++u) {
            turned.covered[turned.index((u + 3) % 144, v)] = image.covered[image.index(u, v)];
            turned.distance[turned.index((u + 3) % 144, v)] = image.distance[image.index(u, v)];
        }
    const auto a = gp::reduce_cylinder_image(image, 48), b = gp::reduce_cylinder_image(turned, 48);
    for (std::uint32_t v = 0; v < 48; ++v)
        for (std::uint32_t u = 0; u < 48; ++u) ASSERT_NEAR(b[v * 48 + (u + 1) % 48], a[v * 48 + u], 1e-6f);
    EXPECT_THROW(gp::reduce_cylinder_image(image, 50), geo::InputError);
}

TEST(Retrieval, PcaKeepsTheVarianceItClaimsAndProjectsLikeTheDatabase) {
    std::mt19937 rng(5);
    std::normal_distribution<float> noise(0.0f, 1.0f);
    const std::size_t n = 30, d = 16 * 16;
    std::vector<std::vector<float>> features(n, std::vector<float>(d));
    for (auto& f : features) {  // three strong directions and a little noise
        const float a = noise(rng), b = noise(rng), c = noise(rng);
        for (std::size_t j = 0; j < d; ++j)
            f[j] = 3.0f * (a * std::sin(float(j)) + b * std::cos(2.0f * float(j)) + c * std::sin(0.3f * float(j))) +
                   0.05f * noise(rng);
    }
    const gp::ShapeDatabase db = gp::build_shape_database(
        features, std::vector<std::string>(n, "x"), std::vector<std::string>(n, "a"), {.size = 32, .reduced = 16});
    EXPECT_GE(db.variance_kept, 0.95);
    EXPECT_LT(db.k, 10u);
    // A model's projection is its stored coefficients.
    const auto c = gp::project_feature(db, features[7]);
    for (std::uint32_t j = 0; j < db.k; ++j) EXPECT_NEAR(c[j], db.coefficients[7][j], 1e-3f);
    // The residual of every model, summed, is the variance the dropped components hold.
    double residual = 0.0, total = 0.0;
    for (const auto& f : features) {
        const auto cf = gp::project_feature(db, f);
        for (std::size_t i = 0; i < d; ++i) {
            double back = db.mean[i];
            for (std::uint32_t j = 0; j < db.k; ++j) back += double(cf[j]) * double(db.loadings[j * d + i]);
            residual += (f[i] - back) * (f[i] - back);
            total += (f[i] - db.mean[i]) * (f[i] - db.mean[i]);
        }
    }
    EXPECT_NEAR(residual / total, 1.0 - db.variance_kept, 1e-4);
    // The file keeps it all.
    const auto path = std::filesystem::path(GIMG_TEST_OUTPUT_DIR) / "shape_db.json";
    gp::write_shape_database(path, db);
    const gp::ShapeDatabase back = gp::read_shape_database(path);
    EXPECT_EQ(back.k, db.k);
    EXPECT_EQ(back.loadings, db.loadings);
    EXPECT_EQ(back.coefficients, db.coefficients);
}

TEST(Retrieval, MeasuresOfAHandRankedList) {
    // Query of class "a" with 3 others of its class among 6 results: a b a c a b.
    const gp::RetrievalScores s = gp::score_ranking({"a", "b", "a", "c", "a", "b"}, "a", 3);
    EXPECT_EQ(s.nearest_neighbour, 1.0);
    EXPECT_NEAR(s.first_tier, 2.0 / 3.0, 1e-12);  // 2 of the top 3
    EXPECT_NEAR(s.second_tier, 1.0, 1e-12);       // all 3 in the top 6
    EXPECT_NEAR(s.average_precision, (1.0 + 2.0 / 3.0 + 3.0 / 5.0) / 3.0, 1e-12);
    const double dcg = 1.0 + 1.0 / std::log2(3.0) + 1.0 / std::log2(5.0);
    const double ideal = 1.0 + 1.0 / std::log2(2.0) + 1.0 / std::log2(3.0);
    EXPECT_NEAR(s.dcg, dcg / ideal, 1e-12);
    const gp::RetrievalScores miss = gp::score_ranking({"b", "a"}, "a", 1);
    EXPECT_EQ(miss.nearest_neighbour, 0.0);
    EXPECT_EQ(miss.first_tier, 0.0);
    EXPECT_NEAR(miss.average_precision, 0.5, 1e-12);
}

namespace {
class RetrievalGpu : public gimg::test::GpuTest {};

geo::Mesh turned(geo::Mesh m, const glm::dmat4& t) {
    for (auto& p : m.positions) p = glm::dvec3(t * glm::dvec4(p, 1.0));
    m.normals.clear();
    return m;
}
}  // namespace

TEST_F(RetrievalGpu, AModelAndATurnedScaledMovedCopyFindEachOtherFirst) {
    std::vector<geo::Mesh> models{geo::make_torus(0.3, 0.1, 48, 24), geo::make_box({0.3, 0.8, 0.5}, 4),
                                  geo::make_icosphere(0.5, 3), geo::make_torus(0.3, 0.03, 48, 24),
                                  geo::make_box({0.2, 1.0, 0.2}, 4)};
    // An elongated, lumpy shape whose PCA axes are well defined.
    geo::Mesh lumpy = geo::make_icosphere(0.5, 4);
    for (auto& p : lumpy.positions) p = glm::dvec3(p.x * 0.6, p.y * 1.5 + 0.2 * std::sin(6.0 * p.x), p.z * 0.8);
    models.push_back(lumpy);
    const std::size_t n = models.size();
    const glm::dmat4 pose = glm::translate(glm::dmat4(1.0), {3.0, -1.0, 2.0}) *
                            glm::rotate(glm::dmat4(1.0), 2.1, glm::normalize(glm::dvec3(1, 2, 3))) *
                            glm::scale(glm::dmat4(1.0), glm::dvec3(2.5));
    for (std::size_t i = 0; i < n; ++i) models.push_back(turned(models[i], pose));
    const auto features = gp::cylinder_features(ctx(), models);
    std::vector<std::string> labels;
    for (std::size_t i = 0; i < 2 * n; ++i) labels.push_back(std::to_string(i % n));
    const gp::ShapeDatabase db = gp::build_shape_database(features, std::vector<std::string>(2 * n, "m"), labels, {});
    for (std::size_t i = 0; i < 2 * n; ++i) {
        // Itself (or its other pose, a tie) at distance 0 when not excluded; its other pose first when it is.
        EXPECT_LT(gp::search_shapes(db, features[i], gp::PoseHandling::BestOfFour).front().distance, 1e-9);
        EXPECT_EQ(gp::search_shapes(db, features[i], gp::PoseHandling::BestOfFour, i).front().model, (i + n) % (2 * n))
            << "model " << i;
    }
}

TEST_F(RetrievalGpu, TheGpuReductionEqualsItsCpuTwin) {
    const std::vector<geo::Mesh> models{geo::make_torus(0.3, 0.1, 48, 24), geo::make_box({0.3, 0.8, 0.5}, 4),
                                        geo::make_icosphere(0.5, 3)};
    const auto gpu = gp::cylinder_features(ctx(), models);
    gp::CylinderZBuffer zbuffer(ctx(), 144, 144);
    ASSERT_EQ(gpu.size(), models.size());
    for (std::size_t i = 0; i < models.size(); ++i) {
        const gp::CylinderImage image =
            zbuffer.project(zbuffer.add_mesh(gp::make_cylinder_mesh(models[i], gp::fit_cylinder_frame(models[i]))));
        const auto cpu = gp::reduce_cylinder_image(image, 48);
        ASSERT_EQ(gpu[i].size(), cpu.size());
        double worst = 0.0, largest = 0.0;
        for (std::size_t j = 0; j < cpu.size(); ++j) {
            worst = std::max(worst, double(std::abs(gpu[i][j] - cpu[j])));
            largest = std::max(largest, double(std::abs(cpu[j])));
        }
        EXPECT_LT(worst, 1e-5) << "model " << i;
        EXPECT_GT(largest, 0.1);
    }
}

TEST(Retrieval, TheThetaSpectrumIsTheSameForEveryTurnAndTheMirror) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> d(-1.0f, 1.0f);
    const std::uint32_t r = 16;
    std::vector<float> image(r * r);
    for (float& v : image) v = d(rng);
    const gp::RetrievalOptions spectrum{.size = 32, .reduced = r, .descriptor = gp::RetrievalDescriptor::ThetaSpectrum};
    const auto a = gp::describe_feature(spectrum, image);
    ASSERT_EQ(a.size(), std::size_t(r * (r / 2 + 1)));
    for (std::uint32_t shift : {1u, 5u, 8u}) {
        std::vector<float> turned(r * r), mirrored(r * r);
        for (std::uint32_t v = 0; v < r; ++v)
            for (std::uint32_t u = 0; u < r; ++u) {
                turned[v * r + (u + shift) % r] = image[v * r + u];
                mirrored[v * r + (r - 1 - u + shift) % r] = image[v * r + u];
            }
        const auto b = gp::describe_feature(spectrum, turned), c = gp::describe_feature(spectrum, mirrored);
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_NEAR(b[i], a[i], 1e-4f);
            ASSERT_NEAR(c[i], a[i], 1e-4f);
        }
    }
    // The image descriptor is the image.
    EXPECT_EQ(gp::describe_feature({.size = 32, .reduced = r}, image), image);
}

TEST_F(RetrievalGpu, ThreeCylindersGiveThreeImagesAndStayPoseInvariantWithTheSpectrum) {
    geo::Mesh lumpy = geo::make_icosphere(0.5, 4);
    for (auto& p : lumpy.positions) p = glm::dvec3(p.x * 0.6, p.y * 1.5 + 0.2 * std::sin(6.0 * p.x), p.z * 0.8);
    const std::vector<geo::Mesh> models{geo::make_torus(0.3, 0.1, 48, 24), geo::make_box({0.3, 0.8, 0.5}, 4), lumpy,
                                        turned(lumpy, glm::rotate(glm::dmat4(1.0), 1.3, glm::dvec3(0.3, 1.0, -0.5)))};
    gp::RetrievalOptions options;
    options.cylinders = 3;
    options.descriptor = gp::RetrievalDescriptor::ThetaSpectrum;
    const auto features = gp::cylinder_features(ctx(), models, options);
    ASSERT_EQ(features.size(), models.size());
    for (const auto& f : features) ASSERT_EQ(f.size(), 3u * 48u * 48u);
    const gp::ShapeDatabase db = gp::build_shape_database(features, std::vector<std::string>(4, "m"),
                                                          {"torus", "box", "lumpy", "lumpy"}, options);
    EXPECT_EQ(gp::search_shapes(db, features[3], gp::PoseHandling::AsAligned, 3).front().model, 2u);
}

TEST(Retrieval, ZernikeMagnitudesIgnoreTurnsAndMirrorsAndTheDiagonalsMayPermute) {
    const std::uint32_t s = 64;
    std::vector<std::uint8_t> shape(s * s), turned(s * s), mirrored(s * s);
    for (std::uint32_t y = 0; y < s; ++y)
        for (std::uint32_t x = 0; x < s; ++x) {  // an off-centre ellipse with a notch
            const double dx = (x - 30.0) / 20.0, dy = (y - 36.0) / 9.0;
            shape[y * s + x] = dx * dx + dy * dy <= 1.0 && !(x > 40 && y < 36);
        }
    for (std::uint32_t y = 0; y < s; ++y)
        for (std::uint32_t x = 0; x < s; ++x) {
            turned[x * s + (s - 1 - y)] = shape[y * s + x];  // a quarter turn
            mirrored[y * s + (s - 1 - x)] = shape[y * s + x];
        }
    const auto a = gp::zernike_magnitudes(shape, s, s), b = gp::zernike_magnitudes(turned, s, s),
               c = gp::zernike_magnitudes(mirrored, s, s);
    ASSERT_EQ(a.size(), 36u);
    EXPECT_NEAR(a[0], 1.0f, 1e-6f);
    for (std::size_t k = 0; k < a.size(); ++k) {
        EXPECT_NEAR(b[k], a[k], 1e-4f) << k;
        EXPECT_NEAR(c[k], a[k], 1e-4f) << k;
    }
    // A descriptor whose diagonal views are swapped as flipping two PCA signs swaps them is at 0.
    std::vector<float> d(7 * 36), e(7 * 36);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (float& v : d) v = u(rng);
    const std::size_t swap[7] = {0, 1, 2, 4, 3, 6, 5};  // the (x, y) flip
    for (std::size_t v = 0; v < 7; ++v)
        for (std::size_t k = 0; k < 36; ++k) e[swap[v] * 36 + k] = d[v * 36 + k];
    EXPECT_EQ(gp::silhouette_distance(d, e), 0.0);
    EXPECT_GT(gp::silhouette_distance(d, std::vector<float>(7 * 36, 0.5f)), 1.0);
}

TEST(Retrieval, TheTwoDimensionalSpectrumIsTheSameTurnedEndOverEnd) {
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> d(-1.0f, 1.0f);
    const std::uint32_t r = 16;
    std::vector<float> image(r * r), over(r * r), turned(r * r);
    for (float& v : image) v = d(rng);
    for (std::uint32_t v = 0; v < r; ++v)
        for (std::uint32_t u = 0; u < r; ++u) {
            over[(r - 1 - v) * r + (r - 1 - u)] = image[v * r + u];  // rows reversed, theta mirrored
            turned[v * r + (u + 3) % r] = image[v * r + u];
        }
    for (auto descriptor : {gp::RetrievalDescriptor::Spectrum2D, gp::RetrievalDescriptor::Spectrum2DSlope}) {
        const gp::RetrievalOptions options{.size = 32, .reduced = r, .descriptor = descriptor};
        const auto a = gp::describe_feature(options, image), b = gp::describe_feature(options, over),
                   c = gp::describe_feature(options, turned);
        const bool slope = descriptor == gp::RetrievalDescriptor::Spectrum2DSlope;
        ASSERT_EQ(a.size(), std::size_t(r * (r / 2 + 1)) * (slope ? 2 : 1));
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_NEAR(b[i], a[i], 1e-3f) << i;
            ASSERT_NEAR(c[i], a[i], 1e-3f) << i;
        }
        if (slope) {  // two halves of unit length
            double first = 0.0, second = 0.0;
            for (std::size_t i = 0; i < a.size() / 2; ++i)
                first += a[i] * a[i], second += a[a.size() / 2 + i] * a[a.size() / 2 + i];
            EXPECT_NEAR(first, 1.0, 1e-5);
            EXPECT_NEAR(second, 1.0, 1e-5);
        }
    }
}

// Panorama's descriptor: the same for the model turned about the axis, mirrored in theta and turned
// end over end (each of its three images), two channels per image each summing to 1, and not the
// same for another image.
TEST(Retrieval, PanoramaIsTheSameTurnedMirroredAndEndOverEnd) {
    constexpr std::uint32_t w = gp::kPanoramaWidth, h = gp::kPanoramaHeight;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> d(0.0f, 1.0f);
    std::vector<float> images(3 * w * h), moved(images.size()), other(images.size());
    for (float& v : images) v = d(rng) < 0.1f ? 0.0f : d(rng);  // some empty pixels
    for (std::uint32_t c = 0; c < 3; ++c)
        for (std::uint32_t y = 0; y < h; ++y)
            for (std::uint32_t x = 0; x < w; ++x) {
                const float v = images[(c * h + y) * w + x];
                // image 0 turned by 17 columns, image 1 mirrored in theta, image 2 end over end
                const std::uint32_t mx = c == 0 ? (x + 17) % w : c == 1 ? w - 1 - x : x, my = c == 2 ? h - 1 - y : y;
                moved[(c * h + my) * w + mx] = v;
                other[(c * h + y) * w + x] = c == 1 && y < h / 2 ? 0.5f : v;
            }
    const gp::RetrievalOptions options{.descriptor = gp::RetrievalDescriptor::Panorama, .cylinders = 3};
    ASSERT_EQ(gp::feature_size(options), images.size());
    const auto a = gp::describe_feature(options, images), b = gp::describe_feature(options, moved),
               c = gp::describe_feature(options, other);
    const std::size_t block = (gp::kPanoramaBand + 1) * (gp::kPanoramaBand + 1);
    ASSERT_EQ(a.size(), 6 * block);
    double changed = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_NEAR(b[i], a[i], 1e-6f) << i;
        changed += std::abs(c[i] - a[i]);
    }
    for (std::size_t k = 0; k < 6; ++k) {
        double sum = 0.0;
        for (std::size_t i = 0; i < block; ++i) sum += a[k * block + i];
        EXPECT_NEAR(sum, 1.0, 1e-5) << "channel " << k;
    }
    EXPECT_GT(changed, 0.05);  // the second image changed: its two channels moved
    EXPECT_THROW(gp::describe_feature(options, std::vector<float>(10)), geo::InputError);
}

// Panorama's images from the GPU Z-buffer equal the CPU ray caster's on the same cylinder meshes
// (distances seen through the axis and empty pixels as 0); every model lies inside its cylinders;
// a turned, scaled, moved copy finds its original first by L1 between the descriptors.
TEST_F(RetrievalGpu, PanoramaImagesEqualTheRayCasterAndFindTurnedCopies) {
    geo::Mesh lumpy = geo::make_icosphere(0.5, 4);
    for (auto& p : lumpy.positions) p = glm::dvec3(p.x * 0.6, p.y * 1.5 + 0.2 * std::sin(6.0 * p.x), p.z * 0.8);
    std::vector<geo::Mesh> models{geo::make_torus(0.3, 0.1, 48, 24), geo::make_box({0.3, 0.8, 0.5}, 4), lumpy,
                                  geo::make_box({0.2, 1.0, 0.2}, 4)};
    const std::size_t n = models.size();
    const glm::dmat4 pose = glm::translate(glm::dmat4(1.0), {3.0, -1.0, 2.0}) *
                            glm::rotate(glm::dmat4(1.0), 2.1, glm::normalize(glm::dvec3(1, 2, 3))) *
                            glm::scale(glm::dmat4(1.0), glm::dvec3(2.5));
    for (std::size_t i = 0; i < n; ++i) models.push_back(turned(models[i], pose));
    const gp::RetrievalOptions options{.descriptor = gp::RetrievalDescriptor::Panorama, .cylinders = 3};
    const auto features = gp::cylinder_features(ctx(), models, options);
    ASSERT_EQ(features.size(), models.size());
    constexpr std::uint32_t w = gp::kPanoramaWidth, h = gp::kPanoramaHeight;
    for (std::size_t m = 0; m < n; ++m) {
        const gp::PanoramaFrame frame = gp::panorama_frame(models[m]);
        for (std::size_t a = 0; a < 3; ++a) {
            const auto& t = frame.transforms[a];
            for (std::size_t i = 0; i < frame.mesh.positions.size(); i += 3) {
                const float x = frame.mesh.positions[i], y = frame.mesh.positions[i + 1],
                            z = frame.mesh.positions[i + 2];
                const float cx = t[0] * x + t[1] * y + t[2] * z + t[3], cy = t[4] * x + t[5] * y + t[6] * z + t[7],
                            cz = t[8] * x + t[9] * y + t[10] * z + t[11];
                ASSERT_LE(std::hypot(cx, cz), 1.0f);
                ASSERT_GE(cy, 0.0f);
                ASSERT_LE(cy, 1.0f);
            }
            const gp::CylinderImage ray = gp::cylinder_raycast(frame.mesh, w, h, t);
            std::size_t differ = 0, seen = 0;
            for (std::size_t i = 0; i < std::size_t(w) * h; ++i) {
                const float expected = ray.covered[i] && ray.distance[i] > 0.0f ? ray.distance[i] : 0.0f;
                const float got = features[m][a * w * h + i];
                differ += std::abs(got - expected) > 1e-5f;
                seen += expected > 0.0f;
            }
            EXPECT_EQ(differ, 0u) << "model " << m << " cylinder " << a;
            EXPECT_GT(seen, std::size_t(w) * h / 20) << "model " << m << " cylinder " << a;  // not empty
        }
    }
    std::vector<std::string> labels;
    for (std::size_t i = 0; i < 2 * n; ++i) labels.push_back(std::to_string(i % n));
    const gp::ShapeDatabase db =
        gp::build_shape_database(features, std::vector<std::string>(2 * n, "m"), labels, options);
    EXPECT_EQ(db.k, 6u * (gp::kPanoramaBand + 1) * (gp::kPanoramaBand + 1));
    EXPECT_TRUE(db.loadings.empty());
    for (std::size_t i = 0; i < 2 * n; ++i)
        EXPECT_EQ(gp::search_shapes(db, features[i], gp::PoseHandling::AsAligned, i).front().model, (i + n) % (2 * n))
            << "model " << i;
    // The file keeps it.
    const auto path = std::filesystem::temp_directory_path() / "gimg_panorama_db.json";
    gp::write_shape_database(path, db);
    const gp::ShapeDatabase back = gp::read_shape_database(path);
    std::filesystem::remove(path);
    EXPECT_EQ(back.options.descriptor, gp::RetrievalDescriptor::Panorama);
    EXPECT_EQ(back.coefficients, db.coefficients);
    // A mesh with no area (collinear points) still gets its three images, as the thesis's
    // descriptor gives it one, rather than stopping a whole index.
    geo::Mesh flat;
    flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    flat.triangles = {{0, 1, 2}};
    const auto flat_feature = gp::cylinder_features(ctx(), {flat}, options);
    ASSERT_EQ(flat_feature.size(), 1u);
    EXPECT_EQ(flat_feature[0].size(), gp::feature_size(options));
}
