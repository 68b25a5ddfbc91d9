// Drawing on an RGBA8 image on the CPU: rectangles and text (stb_easy_font, a segment font made
// of axis-aligned quads, scaled by an integer factor). Used for the labels and the legend of
// `quadplan compare` after the tiles are read back.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace qp::cli {

struct Rgb {
    uint8_t r, g, b;
};

struct RgbaImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> pixels;  // rows top to bottom

    void fill(int x, int y, int w, int h, Rgb color);  // clipped to the image
};

// Size in pixels of `text` (one line) at `scale`.
int textWidth(const std::string& text, int scale);
int textHeight(int scale);

// Draws one line with its top-left corner at (x, y); returns its width.
int drawText(RgbaImage& image, int x, int y, const std::string& text, int scale, Rgb color);

// Splits `text` into lines no wider than `maxWidth` pixels at `scale`, at spaces.
std::vector<std::string> wrapText(const std::string& text, int maxWidth, int scale);

}  // namespace qp::cli
