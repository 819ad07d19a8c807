#include "penumbra/scene/pbrt_spectra.h"

#include <cmath>
#include <map>

namespace penumbra {

namespace {

// One lobe of the CIE 1931 fit: a Gaussian with different widths on each side of its mean.
double lobe(double x, double mu, double s1, double s2) {
  const double t = (x - mu) / (x < mu ? s1 : s2);
  return std::exp(-0.5 * t * t);
}

// The CIE 1931 2-degree colour matching functions by the multi-lobe fit of Wyman, Sloan, Shirley
// 2013, "Simple Analytic Approximations to the CIE XYZ Color Matching Functions" (JCGT 2(2)).
void cie_xyz(double nm, double& x, double& y, double& z) {
  x = 1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7) -
      0.065 * lobe(nm, 501.1, 20.4, 26.2);
  y = 0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1);
  z = 1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8);
}

struct ComplexIor {
  Rgb eta, k;
};

// RGB reductions of measured optical constants, from Tungsten's ComplexIorData.hpp (Benedikt
// Bitterli, tunabrain/tungsten; the same values penumbra's docs quote for gold). pbrt-v4's named
// metal spectra come from the same kind of measured tables.
const std::map<std::string, ComplexIor>& metals() {
  static const std::map<std::string, ComplexIor> m = {
      {"Ag",
       {{0.1552646489f, 0.1167232965f, 0.1383806959f},
        {4.8283433224f, 3.1222459278f, 2.1469504455f}}},
      {"Al",
       {{1.6574599595f, 0.8803689579f, 0.5212287346f},
        {9.2238691996f, 6.2695232477f, 4.8370012281f}}},
      {"Au",
       {{0.1431189557f, 0.3749570432f, 1.4424785571f},
        {3.9831604247f, 2.3857207478f, 1.6032152899f}}},
      {"Cu",
       {{0.2004376970f, 0.9240334304f, 1.1022119527f},
        {3.9129485033f, 2.4528477015f, 2.1421879552f}}},
      {"MgO", {{2.0895885542f, 1.6507224525f, 1.5948759692f}, {0.0f, 0.0f, 0.0f}}},
      {"TiO2",
       {{3.4566203131f, 2.8017076558f, 2.9051485020f}, {0.0001026662f, 0.0f, 0.0006356902f}}},
  };
  return m;
}

// Planck's law: spectral radiance of a blackbody at `kelvin`, at `nm` nanometres (any unit).
double planck(double nm, double kelvin) {
  constexpr double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
  const double l = nm * 1e-9;
  return 2 * h * c * c / (std::pow(l, 5) * (std::exp(h * c / (l * kb * kelvin)) - 1));
}

// XYZ to linear sRGB (IEC 61966-2-1, D65 white).
Rgb xyz_to_rgb(double X, double Y, double Z) {
  return {float(3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z),
          float(-0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z),
          float(0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z)};
}

// Linear sRGB of the spectrum f(nm), integrated against the matching functions over 360-830 nm
// in 1 nm steps; `y` receives the luminance integral.
template <class F>
Rgb spectrum_rgb(F f, double& y) {
  double X = 0, Y = 0, Z = 0;
  for (int nm = 360; nm <= 830; ++nm) {
    const double v = f(double(nm));
    double x, yy, z;
    cie_xyz(nm, x, yy, z);
    X += v * x, Y += v * yy, Z += v * z;
  }
  y = Y;
  return xyz_to_rgb(X, Y, Z);
}

// A piecewise-linear spectrum through (wavelength, value) pairs, constant beyond its ends.
double sampled(const std::vector<double>& pairs, double nm) {
  const size_t n = pairs.size() / 2;
  if (nm <= pairs[0]) return pairs[1];
  for (size_t i = 1; i < n; ++i) {
    const double l0 = pairs[2 * i - 2], l1 = pairs[2 * i];
    if (nm <= l1) {
      const double t = l1 > l0 ? (nm - l0) / (l1 - l0) : 1.0;
      return pairs[2 * i - 1] + t * (pairs[2 * i + 1] - pairs[2 * i - 1]);
    }
  }
  return pairs[2 * n - 1];
}

}  // namespace

Rgb blackbody_rgb(double kelvin) {
  double y;
  const Rgb c = spectrum_rgb([&](double nm) { return planck(nm, kelvin); }, y);
  return c * float(1.0 / y);
}

Rgb sampled_spectrum_rgb(const std::vector<double>& pairs, bool illuminant) {
  double y;
  const Rgb c = spectrum_rgb([&](double nm) { return sampled(pairs, nm); }, y);
  if (illuminant) return y > 0 ? c * float(1.0 / y) : Rgb(0.0f);
  // A reflectance seen under a white light (a 6504 K blackbody, the colour temperature of
  // D65), divided channel by channel by the light's own colour, so a flat spectrum of value v is
  // exactly (v, v, v).
  double yw, yr;
  const Rgb white = spectrum_rgb([&](double nm) { return planck(nm, 6504.0); }, yw);
  const Rgb lit =
      spectrum_rgb([&](double nm) { return sampled(pairs, nm) * planck(nm, 6504.0); }, yr);
  return {lit.r / white.r, lit.g / white.g, lit.b / white.b};
}

std::optional<Rgb> named_metal_rgb(const std::string& name, std::string* substitute) {
  // "metal-NAME-eta" or "metal-NAME-k".
  if (name.rfind("metal-", 0) != 0) return std::nullopt;
  const size_t dash = name.rfind('-');
  if (dash <= 6) return std::nullopt;
  std::string metal = name.substr(6, dash - 6);
  const std::string part = name.substr(dash + 1);
  if (part != "eta" && part != "k") return std::nullopt;
  if (metal == "CuZn") {
    if (substitute) *substitute = "brass (metal-CuZn) has no RGB reduction here; copper's is used";
    metal = "Cu";
  }
  const auto it = metals().find(metal);
  if (it == metals().end()) return std::nullopt;
  return part == "eta" ? it->second.eta : it->second.k;
}

std::optional<float> named_glass_ior(const std::string& name) {
  // n_d of the SCHOTT catalogue glasses whose dispersion pbrt-v4 tabulates (N-BK7, N-BAF10,
  // N-FK51A, N-LASF9, SF5, SF10, SF11).
  static const std::map<std::string, float> g = {{"glass-BK7", 1.5168f},   {"glass-BAF10", 1.6700f},
                                                 {"glass-FK51A", 1.4866f}, {"glass-LASF9", 1.8503f},
                                                 {"glass-F5", 1.6727f},    {"glass-F10", 1.7284f},
                                                 {"glass-F11", 1.7847f}};
  const auto it = g.find(name);
  if (it == g.end()) return std::nullopt;
  return it->second;
}

Rgb pbrt_color(const PbrtParam& p, bool illuminant, std::vector<std::string>& warnings) {
  if (p.type == "rgb") {
    if (p.numbers.size() != 3)
      p.loc.fail("parameter " + p.declaration() + " takes 3 values, got " +
                 std::to_string(p.numbers.size()));
    return {float(p.numbers[0]), float(p.numbers[1]), float(p.numbers[2])};
  }
  if (p.type == "blackbody") return blackbody_rgb(p.numbers[0]);
  if (p.type == "float") {  // a grey value where pbrt takes float or spectrum
    if (p.numbers.size() != 1) p.loc.fail("parameter " + p.declaration() + " takes one value");
    return Rgb(float(p.numbers[0]));
  }
  if (p.type != "spectrum") p.loc.fail("parameter " + p.declaration() + " is not a colour");
  if (!p.strings.empty()) {
    const std::string& name = p.strings[0];
    std::string note;
    if (auto rgb = named_metal_rgb(name, &note)) {
      if (!note.empty()) pbrt_warn(warnings, p.loc, note);
      return *rgb;
    }
    if (name.rfind("stdillum-", 0) == 0) {
      if (name != "stdillum-D65")
        pbrt_warn(warnings, p.loc, "spectrum \"" + name + "\" taken as white (stdillum-D65)");
      return Rgb(1.0f);
    }
    p.loc.fail("spectrum \"" + name +
               "\": named spectra other than metal-*-eta/k and stdillum-* and spectrum files "
               "are not supported");
  }
  if (p.numbers.size() == 1) return Rgb(float(p.numbers[0]));  // a constant spectrum
  // (wavelength, value) pairs, in increasing wavelength.
  for (size_t i = 2; i < p.numbers.size(); i += 2)
    if (p.numbers[i] < p.numbers[i - 2])
      p.loc.fail("parameter " + p.declaration() + ": wavelengths must increase");
  return sampled_spectrum_rgb(p.numbers, illuminant);
}

}  // namespace penumbra
