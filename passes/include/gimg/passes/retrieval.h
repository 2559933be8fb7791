#pragma once
// 3D model retrieval from cylindrical images (the cylindrical-projection thesis, chapter 5;
// docs/retrieval.md): every model's 144 x 144 cylindrical image (the GPU Z-buffer), low-passed and
// reduced to 48 x 48, projected on the principal components holding 95 % of the database's
// variance; the nearest models by squared distance between those coefficients.

#include "gimg/engine/context.h"
#include "gimg/geometry/mesh.h"
#include "gimg/passes/cylinder.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace gimg::passes {

// What the PCA sees of a reduced image.
enum class RetrievalDescriptor {
    Image,            // its reduced^2 values (the thesis)
    ThetaSpectrum,    // per row, the magnitudes of its DFT over theta (reduced / 2 + 1 of them):
                      // the same for every turn of the model about its axis, and for its mirror image
    Spectrum2D,       // the magnitudes of the image's 2D DFT (reduced / 2 + 1 frequencies in theta, all
                      // reduced in height): as ThetaSpectrum, and also the same turned end over end
    Spectrum2DSlope,  // Spectrum2D of the image followed by Spectrum2D of its slope (the length of its
                      // central-difference gradient, circular in theta), each half scaled to unit
                      // length: a second channel as PANORAMA's normals give one; the same invariances
    // In PANORAMA's manner (Papadakis et al. 2010), its own images and no PCA: the model in its
    // area-weighted principal frame, scaled by its mean distance from the centroid (radius 3 of
    // them, height 6, more where the model reaches farther); a kPanoramaWidth x kPanoramaHeight
    // image around each principal axis, and per image two channels, the distance from the axis
    // and the cosine between the wall's ray and the surface the image's slope gives; each channel
    // the magnitudes of its 2D DFT at the (kPanoramaBand + 1)^2 lowest frequencies, the same
    // turned about the axis, mirrored or end over end, scaled to sum 1; compared by L1.
    Panorama,
};

inline constexpr std::uint32_t kPanoramaWidth = 128, kPanoramaHeight = 64, kPanoramaBand = 20;

struct RetrievalOptions {
    std::uint32_t size = 144;    // the cylindrical image is size x size
    std::uint32_t reduced = 48;  // reduced to reduced x reduced (size must be a multiple of it)
    double variance = 0.95;      // the smallest k principal components holding this share
    RetrievalDescriptor descriptor = RetrievalDescriptor::Image;
    // 1: the cylinder around the main axis (the thesis). 3: one around each principal axis, as
    // PANORAMA does; the feature is the three reduced images one after another.
    std::uint32_t cylinders = 1;
};

// The descriptor of a feature (its own values, or the per-row spectrum magnitudes; Panorama's two
// channels' spectra).
std::vector<float> describe_feature(const RetrievalOptions& options, const std::vector<float>& reduced_image);
// The values a feature holds: cylinders x reduced^2, or Panorama's three images.
std::size_t feature_size(const RetrievalOptions& options);

// The feature of one cylindrical image: low-pass and decimation in one step (the thesis's "cubic
// reduction"), each output pixel the Keys cubic kernel stretched by the reduction factor over the
// input pixels around its centre, normalised; circular in theta, clamped in height. Empty pixels
// count as d = 0. reduced x reduced values, row-major from the top row.
std::vector<float> reduce_cylinder_image(const CylinderImage& image, std::uint32_t reduced);

// The features of many meshes: each aligned by fit_cylinder_frame, projected by the GPU Z-buffer and
// reduced by a compute pass in the same graph (reduce_cylinder_image is its CPU twin), in batches;
// with 3 cylinders, the model's principal axes each take the cylinder's axis in turn. Panorama:
// its three images (panorama_frame) as the Z-buffer leaves them, empty and negative
// distances (surfaces seen through the axis) as 0.
std::vector<std::vector<float>> cylinder_features(Context& ctx, const std::vector<geo::Mesh>& meshes,
                                                  const RetrievalOptions& options = {});

// Panorama's frame of one model: the mesh in its area-weighted principal frame, scaled by its mean
// distance from the centroid (a mesh with no area: the identity frame about its vertices'
// centroid), and the three transforms into the cylinder (main, second, third principal axis on
// the cylinder's): radii over R = max(3, the farthest point from that axis), heights over [-H, H]
// with H = max(R, the farthest point along it), so the model lies inside. One upload, three images.
struct PanoramaFrame {
    CylinderMesh mesh;
    std::array<CylinderTransform, 3> transforms;
};
PanoramaFrame panorama_frame(const geo::Mesh& mesh);

// PCA leaves each axis's sign open, so one model can come out turned over. BestOfFour compares a
// query in the four poses the two free signs give (turned end over end, turned half way about
// the axis, both) and keeps the nearest; with 3 cylinders it compares as aligned.
enum class PoseHandling { AsAligned, BestOfFour };

struct ShapeDatabase {
    RetrievalOptions options;
    std::uint32_t k = 0;                           // principal components kept
    double variance_kept = 0.0;                    // their share of the variance
    std::vector<float> mean;                       // the descriptor's size
    std::vector<float> loadings;                   // descriptor size x k, column after column
    std::vector<std::vector<float>> coefficients;  // k per model (Panorama: the descriptor, k its size)
    std::vector<std::string> paths, labels;        // per model; labels may be empty strings
    std::size_t size() const { return coefficients.size(); }
};

// PCA of the centred descriptors of the features (reduced images; Eigen's SVD; Panorama keeps its
// descriptors as they are: panorama_database); throws geo::InputError for fewer than 2 models or
// features of different sizes.
ShapeDatabase build_shape_database(const std::vector<std::vector<float>>& features, std::vector<std::string> paths,
                                   std::vector<std::string> labels, const RetrievalOptions& options);
// Every feature's descriptor, the features spread over the cores.
std::vector<std::vector<float>> describe_features(const RetrievalOptions& options,
                                                  const std::vector<std::vector<float>>& features);
// A Panorama database of descriptors already made (describe_features), for callers that keep
// descriptors rather than the larger features.
ShapeDatabase panorama_database(std::vector<std::vector<float>> descriptors, std::vector<std::string> paths,
                                std::vector<std::string> labels);

// The k coefficients of a feature (a reduced image).
std::vector<float> project_feature(const ShapeDatabase& db, const std::vector<float>& feature);

struct ShapeMatch {
    std::size_t model = 0;
    double distance = 0.0;  // squared distance between coefficients (Panorama: L1 between descriptors)
};
// Every model but `exclude` (e.g. the query itself), nearest first.
std::vector<ShapeMatch> search_shapes(const ShapeDatabase& db, const std::vector<float>& feature, PoseHandling pose,
                                      std::size_t exclude = static_cast<std::size_t>(-1));

// A documented JSON file (docs/retrieval.md), written atomically; reading checks every array's size.
void write_shape_database(const std::filesystem::path& path, const ShapeDatabase& db);
ShapeDatabase read_shape_database(const std::filesystem::path& path);

// The D2 shape distribution (Osada et al. 2002), the cheap floor retrieval is measured against:
// the histogram of distances between 1,024 area-uniform surface points (all pairs), over [0, 3
// mean distance) in `bins` bins, normalised to sum 1. Compare two with the L1 distance.
std::vector<float> d2_histogram(const geo::Mesh& mesh, std::uint32_t bins = 64);

// The silhouette baseline, in the spirit of the Light Field Descriptor (Chen et al. 2003): the model
// in its principal frame drawn as a silhouette (128 x 128, the renderer) along 7 lines, the three
// principal axes and the four diagonals (1, +-1, +-1); each silhouette described by the magnitudes
// of its Zernike moments up to order 10 (36 values, divided by the zeroth: invariant to turning,
// mirroring and scaling the silhouette).
std::vector<float> silhouette_descriptor(Context& ctx, const geo::Mesh& mesh);
// Zernike magnitudes of a binary image (width x height, 1 inside), about its centroid, scaled to
// its farthest pixel: n <= 10, m = n, n - 2, ... >= 0, |Z_nm| / |Z_00|.
std::vector<float> zernike_magnitudes(const std::vector<std::uint8_t>& inside, std::uint32_t width,
                                      std::uint32_t height);
// The distance between two silhouette descriptors: L1 over the axis views plus the smallest L1 over
// the four ways PCA's free signs can permute the diagonal views.
double silhouette_distance(const std::vector<float>& a, const std::vector<float>& b);

// The Princeton Shape Benchmark's measures of one ranked list for a query of `label`: nearest
// neighbour, first and second tier, normalised DCG and average precision; relevant = same label.
struct RetrievalScores {
    double nearest_neighbour = 0.0, first_tier = 0.0, second_tier = 0.0, dcg = 0.0, average_precision = 0.0;
};
RetrievalScores score_ranking(const std::vector<std::string>& ranked_labels, const std::string& label,
                              std::size_t relevant);

}  // namespace gimg::passes
