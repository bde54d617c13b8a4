// PNG and PFM files: the PFM contract (rows bottom to top, +inf for misses).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/math/ray.h"
#include "core/render/image.h"

using namespace accelviz;

namespace {
std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("accelviz_test_" + name)).string();
}
}  // namespace

TEST(PfmFile, HeaderAndBottomToTopRows) {
    const int w = 3, h = 2;
    const std::vector<float> depth = {1, 2, 3, 4, 5, kInfinity};  // top row first in memory
    const std::string path = temp_path("depth.pfm");
    ASSERT_FALSE(write_pfm(depth, w, h, path).has_value());
    std::ifstream in(path, std::ios::binary);
    std::string content((std::istreambuf_iterator<char>(in)), {});
    const std::string header = "Pf\n3 2\n-1.0\n";
    ASSERT_EQ(content.substr(0, header.size()), header);
    ASSERT_EQ(content.size(), header.size() + 6 * sizeof(float));
    float first_row[3];
    std::memcpy(first_row, content.data() + header.size(), sizeof first_row);
    EXPECT_EQ(first_row[0], 4);  // the file starts with the BOTTOM row
    EXPECT_TRUE(std::isinf(first_row[2]));
    int rw = 0, rh = 0;
    auto back = read_pfm(path, &rw, &rh);
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(*back, depth);
}

TEST(PngFile, RoundTrip) {
    Image img(4, 3, {10, 20, 30});
    img.at(3, 2) = {255, 0, 7};
    const std::string path = temp_path("img.png");
    ASSERT_FALSE(write_png(img, path).has_value());
    auto back = read_png(path);
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(back->pixels, img.pixels);
}

TEST(PngFile, UnwritablePathIsAnError) {
    auto err = write_png(Image(2, 2), "/nonexistent-dir/x.png");
    ASSERT_TRUE(err.has_value());
    EXPECT_NE(err->message.find("/nonexistent-dir/x.png"), std::string::npos);
}

TEST(TextLabels, DrawTextPutsInkInsideItsBox) {
    Image img(200, 50);
    draw_text(img, 5, 5, "Ray cast", 2, {255, 255, 255});
    int w = 0, h = 0;
    text_size("Ray cast", 2, &w, &h);
    int ink = 0, outside = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (img.at(x, y).r == 255) {
                ++ink;
                if (x < 5 || y < 5 || x >= 5 + w || y >= 5 + h) ++outside;
            }
    EXPECT_GT(ink, 50);
    EXPECT_EQ(outside, 0);
}
