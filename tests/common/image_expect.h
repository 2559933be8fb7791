#pragma once
// Image-diff assertions for every image test: compare with a stated tolerance (per-channel
// difference, share of differing pixels); on failure the actual picture and a diff picture are
// written beside each other in build/test-output/<folder>/ and their paths printed.
// GIMG_UPDATE_GOLDEN=1 rewrites golden files from the actual output instead of comparing.

#include "gimg/geometry/image.h"

#include "test_data.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace gimg::test {

inline std::filesystem::path golden_path(const std::string& name) {
    return std::filesystem::path(GIMG_TEST_DATA_DIR) / "golden" / name;
}

inline ::testing::AssertionResult images_match(const geo::RgbaImage& actual, const geo::RgbaImage& expected,
                                               int channel_tolerance, double max_differing_share,
                                               const std::string& name) {
    const geo::ImageDifference d = geo::compare_images(actual, expected, channel_tolerance);
    if (d.same_size && d.differing_share <= max_differing_share) return ::testing::AssertionSuccess();
    const auto dir = output_dir("image-diff");
    const auto stem = std::filesystem::path(name).stem().string();
    geo::write_png(actual, dir / (stem + ".actual.png"));
    if (d.same_size) geo::write_png(d.diff, dir / (stem + ".diff.png"));
    return ::testing::AssertionFailure() << name << ": " << (d.same_size ? "" : "sizes differ; ") << d.differing_pixels
                                         << " pixels (" << 100.0 * d.differing_share << " %) differ by more than "
                                         << channel_tolerance << " (allowed " << 100.0 * max_differing_share
                                         << " %), max difference " << d.max_abs_difference << "; see " << dir / stem
                                         << ".{actual,diff}.png";
}

inline ::testing::AssertionResult matches_golden(const geo::RgbaImage& actual, const std::string& name,
                                                 int channel_tolerance, double max_differing_share) {
    const auto path = golden_path(name);
    if (const char* update = std::getenv("GIMG_UPDATE_GOLDEN"); update && std::string(update) == "1") {
        geo::write_png(actual, path);
        return ::testing::AssertionSuccess() << "golden " << path << " rewritten";
    }
    if (!std::filesystem::exists(path))
        return ::testing::AssertionFailure()
               << "golden image " << path << " is missing (GIMG_UPDATE_GOLDEN=1 makes it)";
    return images_match(actual, geo::read_png(path), channel_tolerance, max_differing_share, name);
}

}  // namespace gimg::test
