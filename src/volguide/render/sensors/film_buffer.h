#pragma once
// Accumulation of filtered samples, hdrfilm style: each sample is splatted with weight
// f(dx) f(dy) to the pixels whose centres lie within the filter radius, and a pixel's value is
// sum(w L) / sum(w). A TileBuffer collects the samples of one tile (pixels around the tile included)
// in float; FilmBuffer adds tiles in double, in the order the caller chooses (the render loop uses
// a fixed order so that images are bit-identical for any thread count).
#include <vector>

#include "volguide/core/color.h"
#include "volguide/core/image.h"
#include "volguide/core/vec.h"
#include "volguide/render/sensor.h"

namespace volguide {

// Pixel rectangle [x0, x1) x [y0, y1).
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    bool empty() const { return x1 <= x0 || y1 <= y0; }
};

// How a filter maps a sample position to pixels.
class Splatter {
  public:
    Splatter(const ReconstructionFilter& filter, int film_width, int film_height);
    // Film pixels a sample at a position inside `samples` can reach (clipped to the film).
    PixelRect footprint(const PixelRect& samples) const;
    const ReconstructionFilter& filter() const { return *filter_; }
    bool is_box() const { return box_; }
    float radius() const { return radius_; }
    int film_width() const { return width_; }
    int film_height() const { return height_; }

  private:
    const ReconstructionFilter* filter_;
    bool box_;
    float radius_;
    int width_, height_;
};

class TileBuffer {
  public:
    // `rect` = the film pixels this buffer covers (Splatter::footprint of the tile's samples).
    TileBuffer(const Splatter& splatter, PixelRect rect, bool second_moment);
    // Adds a sample at continuous film position `pos` (pixel (i, j) spans [i, i+1) x [j, j+1)).
    void splat(Point2f pos, const Color3& value);
    const PixelRect& rect() const { return rect_; }

  private:
    friend class FilmBuffer;
    const Splatter* splatter_;
    PixelRect rect_;
    bool second_moment_;
    std::vector<float> weight_;
    std::vector<Color3> sum_, sum2_;
};

// A FilmBuffer's sums as they are (render checkpoints, integrators/render_state.h): per pixel sum(w),
// then 3 doubles each of sum(w L) and (with second moments; else empty) sum(w L^2), row-major.
struct FilmSums {
    std::vector<double> weight, sum, sum2;
};

class FilmBuffer {
  public:
    FilmBuffer(int width, int height, bool second_moment);
    void add(const TileBuffer& tile);
    // sum(w L) / sum(w) per pixel (0 where no weight arrived).
    Image mean() const;
    // Per-sample variance sum(w L^2) / sum(w) - mean^2 (clamped at 0); empty without second moments.
    Image variance() const;
    // sum(w) per pixel, row-major.
    const std::vector<double>& weights() const { return weight_; }
    FilmSums sums() const { return {weight_, sum_, sum2_}; }
    // Replaces the sums (a resumed render's); throws std::invalid_argument when their sizes are not
    // this film's (another resolution, second moments or not).
    void restore(FilmSums sums);
    int width() const { return width_; }
    int height() const { return height_; }

  private:
    int width_, height_;
    bool second_moment_;
    std::vector<double> weight_, sum_, sum2_;  // sums are 3 doubles per pixel
};

}  // namespace volguide
