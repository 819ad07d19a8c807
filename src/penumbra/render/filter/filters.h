#pragma once
/// The reconstruction filters: box, tent, Gaussian and Mitchell-Netravali.
#include "penumbra/core/params.h"
#include "penumbra/render/filter/filter.h"

namespace penumbra {

/// Box: 1 on (-radius, radius); radius 0.5 (the default) is the mean over the pixel square.
class BoxFilter final : public Filter {
 public:
  explicit BoxFilter(const ParamList& p);
  std::string name() const override;
  float radius() const override { return radius_; }
  float eval(float x) const override { return x > -radius_ && x < radius_ ? 1.0f : 0.0f; }

 private:
  float radius_;
};

/// Tent (triangle): max(0, radius - |x|); default radius 1.
class TentFilter final : public Filter {
 public:
  explicit TentFilter(const ParamList& p);
  std::string name() const override;
  float radius() const override { return radius_; }
  float eval(float x) const override;

 private:
  float radius_;
};

/// Gaussian exp(-x^2 / (2 sigma^2)) minus its value at the radius (so it reaches zero there);
/// defaults radius 1.5, sigma 0.5.
class GaussianFilter final : public Filter {
 public:
  explicit GaussianFilter(const ParamList& p);
  std::string name() const override;
  float radius() const override { return radius_; }
  float eval(float x) const override;

 private:
  float radius_, sigma_, offset_;
};

/// Mitchell-Netravali cubic (Mitchell, Netravali 1988, "Reconstruction Filters in Computer
/// Graphics"), with parameters b and c (default 1/3, 1/3) over radius 2 (default), scaled so that
/// its support is [-radius, radius]. Negative lobes sharpen.
class MitchellFilter final : public Filter {
 public:
  explicit MitchellFilter(const ParamList& p);
  std::string name() const override;
  float radius() const override { return radius_; }
  float eval(float x) const override;

 private:
  float radius_, b_, c_;
};

}  // namespace penumbra
