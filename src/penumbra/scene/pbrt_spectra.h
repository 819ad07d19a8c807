#pragma once
/// Colours from pbrt-v4 spectral parameters: "rgb" values (linear sRGB), "blackbody" temperatures
/// and the named spectra of metals and glasses, reduced to the RGB (or single ior) that penumbra's
/// materials and lights take.
#include <optional>
#include <string>
#include <vector>

#include "penumbra/core/color.h"
#include "penumbra/scene/pbrt_params.h"

namespace penumbra {

/// Linear sRGB of a blackbody at `kelvin`, scaled to luminance Y = 1 as pbrt-v4 normalises the
/// spectra of lights (so "blackbody L [T]" is as bright as "rgb L [1 1 1]").
Rgb blackbody_rgb(double kelvin);

/// The RGB reduction of a named pbrt-v4 metal spectrum ("metal-Cu-eta", "metal-Au-k", ...), or
/// nullopt for an unknown name. `substitute` is set to a note when the value stands in for a metal
/// that has no RGB reduction here (metal-CuZn uses copper).
std::optional<Rgb> named_metal_rgb(const std::string& name, std::string* substitute = nullptr);

/// The index of refraction at 587.6 nm (the d line) of a named pbrt-v4 glass ("glass-BK7", ...),
/// or nullopt.
std::optional<float> named_glass_ior(const std::string& name);

/// Linear sRGB of a piecewise-linear spectrum given as (wavelength in nm, value) pairs: an
/// `illuminant` is normalised to luminance Y = 1 (as pbrt-v4 normalises light spectra); a
/// reflectance is its colour under a 6504 K blackbody divided by that light's colour, so that a
/// flat spectrum of value v gives exactly (v, v, v).
Rgb sampled_spectrum_rgb(const std::vector<double>& pairs, bool illuminant);

/// The value of a colour parameter (rgb, blackbody, float or spectrum) as RGB; `illuminant` for
/// the spectra of lights (see sampled_spectrum_rgb). A spectrum of one value is that constant. A
/// named spectrum other than a metal's or stdillum-*, or a spectrum file, is an error at the
/// parameter.
Rgb pbrt_color(const PbrtParam& p, bool illuminant, std::vector<std::string>& warnings);

}  // namespace penumbra
