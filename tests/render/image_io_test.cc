// Tests for image_io.h: PFM, OpenEXR and PNG round trips keep values and row order.
#include <gtest/gtest.h>
#include <lixel/render/image_io.h>

#include <filesystem>
#include <random>
#include <string>

namespace lixel::render {
namespace {

std::string TempPath(const std::string& name) {
    return (std::filesystem::temp_directory_path() /
            ("lixel_" + std::to_string(::getpid()) + "_" + name))
        .string();
}

FloatImage RandomImage(int width, int height, int channels, std::mt19937& rng) {
    FloatImage image{width, height, channels, {}};
    std::uniform_real_distribution<float> value(-2.0f, 2.0f);
    image.pixels.resize(static_cast<std::size_t>(width) * height * channels);
    for (float& v : image.pixels) v = value(rng);
    return image;
}

TEST(Pfm, RoundTripsOneTwoAndThreeChannelsBitExact) {
    std::mt19937 rng(12351);
    for (int channels : {1, 2, 3}) {
        const FloatImage image = RandomImage(17, 9, channels, rng);
        const std::string path = TempPath("round_trip.pfm");
        ASSERT_TRUE(WritePfm(path, image).ok());
        auto read = ReadPfm(path);
        ASSERT_TRUE(read.ok()) << read.error().Message();
        EXPECT_EQ(read->width, 17);
        EXPECT_EQ(read->height, 9);
        EXPECT_EQ(read->channels, channels == 1 ? 1 : 3);
        for (int y = 0; y < 9; ++y) {
            for (int x = 0; x < 17; ++x) {
                for (int c = 0; c < channels; ++c) {
                    ASSERT_EQ(read->at(x, y, c), image.at(x, y, c)) << x << "," << y << "," << c;
                }
                if (channels == 2) {
                    ASSERT_EQ(read->at(x, y, 2), 0.0f);
                }
            }
        }
        std::filesystem::remove(path);
    }
}

TEST(Pfm, RefusesBadImagesAndFiles) {
    EXPECT_FALSE(WritePfm(TempPath("bad.pfm"), FloatImage{2, 2, 1, {1.0f}}).ok());
    EXPECT_FALSE(WritePfm("/nonexistent/dir/x.pfm", FloatImage{1, 1, 1, {1.0f}}).ok());
    EXPECT_FALSE(ReadPfm("/nonexistent/x.pfm").ok());
    const std::string path = TempPath("not.pfm");
    {
        std::FILE* f = std::fopen(path.c_str(), "wb");
        std::fputs("P6\n1 1\n255\nabc", f);
        std::fclose(f);
    }
    auto read = ReadPfm(path);
    ASSERT_FALSE(read.ok());
    EXPECT_EQ(read.error().field, "path");
    std::filesystem::remove(path);
}

TEST(Exr, RoundTripsOneToFourChannelsBitExactWithRowOrder) {
    std::mt19937 rng(12351);
    for (int channels : {1, 2, 3, 4}) {
        const FloatImage image = RandomImage(13, 7, channels, rng);
        const std::string path = TempPath("round_trip.exr");
        ASSERT_TRUE(WriteExr(path, image).ok());
        auto read = ReadExr(path);
        ASSERT_TRUE(read.ok()) << read.error().Message();
        EXPECT_EQ(read->width, 13);
        EXPECT_EQ(read->height, 7);
        EXPECT_EQ(read->channels, channels);
        EXPECT_EQ(read->pixels, image.pixels);
        std::filesystem::remove(path);
    }
    EXPECT_FALSE(ReadExr("/nonexistent/x.exr").ok());
    EXPECT_FALSE(WriteExr(TempPath("bad.exr"), FloatImage{2, 2, 5, {}}).ok());
}

TEST(Png, RoundTripsBytesWithRowOrder) {
    std::mt19937 rng(12351);
    Rgb8Image image{11, 5, {}};
    for (int i = 0; i < 11 * 5 * 3; ++i) image.pixels.push_back(static_cast<std::uint8_t>(rng()));
    const std::string path = TempPath("round_trip.png");
    ASSERT_TRUE(WritePng(path, image).ok());
    auto read = ReadPng(path);
    ASSERT_TRUE(read.ok()) << read.error().Message();
    EXPECT_EQ(read->width, 11);
    EXPECT_EQ(read->height, 5);
    EXPECT_EQ(read->pixels, image.pixels);
    std::filesystem::remove(path);
    EXPECT_FALSE(ReadPng("/nonexistent/x.png").ok());
    // A buffer one byte short, or an empty image, is refused naming the path; nothing is written.
    const std::string refused = TempPath("refused.png");
    image.pixels.pop_back();
    for (const Rgb8Image& bad : {image, Rgb8Image{0, 5, {}}}) {
        auto written = WritePng(refused, bad);
        ASSERT_FALSE(written.ok());
        EXPECT_EQ(written.error().field, refused);
        EXPECT_NE(written.error().reason.find("3 * width * height"), std::string::npos);
    }
    EXPECT_FALSE(std::filesystem::exists(refused));
}

TEST(MaskPreview, GreyForLitFractionBlueForNoSurface) {
    const Rgb8Image p = MaskPreview(FloatImage{3, 1, 1, {0.0f, 1.0f, -1.0f}});
    EXPECT_EQ(p.pixels, (std::vector<std::uint8_t>{0, 0, 0, 255, 255, 255, 40, 60, 140}));
}

}  // namespace
}  // namespace lixel::render
