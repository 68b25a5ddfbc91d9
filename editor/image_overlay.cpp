#include "image_overlay.h"

#include <algorithm>
#include <sstream>

// A header of static functions, not all of which we call.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

namespace qp::cli {

void RgbaImage::fill(int x, int y, int w, int h, Rgb color) {
    const int x0 = std::max(x, 0), y0 = std::max(y, 0);
    const int x1 = std::min(x + w, int(width)), y1 = std::min(y + h, int(height));
    for (int py = y0; py < y1; ++py)
        for (int px = x0; px < x1; ++px) {
            uint8_t* p = &pixels[(size_t(py) * width + size_t(px)) * 4];
            p[0] = color.r;
            p[1] = color.g;
            p[2] = color.b;
            p[3] = 255;
        }
}

int textWidth(const std::string& text, int scale) {
    std::string copy = text;
    return stb_easy_font_width(copy.data()) * scale;
}

// stb_easy_font draws capitals 7 units tall from y + 1, descenders to about y + 10.
int textHeight(int scale) { return 11 * scale; }

int drawText(RgbaImage& image, int x, int y, const std::string& text, int scale, Rgb color) {
    struct Vertex {
        float x, y, z;
        uint8_t color[4];
    };
    std::vector<Vertex> quads(text.size() * 70 + 4);  // ~270 bytes a character (stb's estimate)
    std::string copy = text;
    const int count = stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, quads.data(), int(quads.size() * sizeof(Vertex)));
    for (int q = 0; q < count; ++q) {
        const Vertex* v = &quads[size_t(q) * 4];
        const float x0 = std::min({v[0].x, v[1].x, v[2].x, v[3].x}), x1 = std::max({v[0].x, v[1].x, v[2].x, v[3].x});
        const float y0 = std::min({v[0].y, v[1].y, v[2].y, v[3].y}), y1 = std::max({v[0].y, v[1].y, v[2].y, v[3].y});
        image.fill(x + int(x0) * scale, y + int(y0) * scale, int(x1 - x0) * scale, int(y1 - y0) * scale, color);
    }
    return textWidth(text, scale);
}

std::vector<std::string> wrapText(const std::string& text, int maxWidth, int scale) {
    std::vector<std::string> lines;
    std::istringstream words(text);
    std::string word, line;
    while (words >> word) {
        const std::string candidate = line.empty() ? word : line + " " + word;
        if (!line.empty() && textWidth(candidate, scale) > maxWidth) {
            lines.push_back(line);
            line = word;
        } else {
            line = candidate;
        }
    }
    if (!line.empty()) lines.push_back(line);
    return lines;
}

}  // namespace qp::cli
