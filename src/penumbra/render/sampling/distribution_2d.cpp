#include "penumbra/render/sampling/distribution_2d.h"

#include "penumbra/core/error.h"

namespace penumbra {

Distribution2D::Distribution2D(std::span<const float> f, int nx, int ny) {
  if (f.empty()) {
    conditional_.emplace_back();
    return;
  }
  if (nx <= 0 || ny <= 0 || f.size() != static_cast<size_t>(nx) * static_cast<size_t>(ny))
    throw Error("Distribution2D: " + std::to_string(f.size()) + " values for " +
                std::to_string(nx) + " x " + std::to_string(ny) + " cells");
  // Conditional densities per row, then the marginal over the rows' integrals.
  conditional_.reserve(ny);
  std::vector<float> row_integrals(ny);
  for (int y = 0; y < ny; ++y) {
    conditional_.emplace_back(f.subspan(static_cast<size_t>(y) * nx, nx));
    row_integrals[y] = static_cast<float>(conditional_.back().integral());
  }
  marginal_ = Distribution1D(row_integrals);
}

Sample2D Distribution2D::sample(Vec2 u) const {
  const Sample1D row = marginal_.sample(u.y);
  const Sample1D col = conditional_[row.cell].sample(u.x);
  Sample2D s;
  s.p = {col.x, row.x};
  s.pdf = row.pdf * col.pdf;
  s.x = col.cell;
  s.y = row.cell;
  return s;
}

}  // namespace penumbra
