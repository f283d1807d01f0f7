#include "clearshape/dsp/sos.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::dsp {

using Complex = std::complex<double>;

SosDesign::SosDesign(std::vector<Section> sections, double sample_rate_hz)
    : sections_(std::move(sections)), sample_rate_hz_(sample_rate_hz) {
  require_positive("sample_rate_hz", sample_rate_hz);
  if (sections_.empty()) {
    throw InvalidArgument("SOS design: needs at least one second-order section");
  }
  for (std::size_t i = 0; i < sections_.size(); ++i) {
    Section& s = sections_[i];
    for (double c : {s.b0, s.b1, s.b2, s.a0, s.a1, s.a2}) {
      if (!std::isfinite(c)) {
        throw InvalidArgument(fmt::format("SOS design: section {} has a non-finite coefficient ({}); "
                                          "check the design that produced it", i + 1, c));
      }
    }
    if (s.a0 == 0.0) {
      throw InvalidArgument(fmt::format("SOS design: section {} has a0 = 0; allowed: a0 != 0 (the "
                                        "leading denominator coefficient)", i + 1));
    }
    if (s.a0 != 1.0) {
      const double a0 = s.a0;
      s = Section{s.b0 / a0, s.b1 / a0, s.b2 / a0, 1.0, s.a1 / a0, s.a2 / a0};
    }
  }
}

std::complex<double> SosDesign::response(double frequency_hz) const noexcept {
  // H(e^{jω}) = Π (b0 + b1 e^{-jω} + b2 e^{-2jω}) / (a0 + a1 e^{-jω} + a2 e^{-2jω}), ω = 2πf/fs.
  const Complex w = std::polar(1.0, -kTwoPi * frequency_hz / sample_rate_hz_);
  Complex h{1.0, 0.0};
  for (const Section& s : sections_) {
    h *= (s.b0 + w * (s.b1 + w * s.b2)) / (s.a0 + w * (s.a1 + w * s.a2));
  }
  return h;
}

double SosDesign::dc_gain() const noexcept {
  double g = 1.0;
  for (const Section& s : sections_) g *= (s.b0 + s.b1 + s.b2) / (s.a0 + s.a1 + s.a2);
  return g;
}

namespace {

bool is_real(const Complex& c) noexcept { return c.imag() == 0.0; }

// scipy _cplxreal: one member (positive imaginary part) of each conjugate pair, sorted by real
// part then |imag|, followed by the real values, sorted.
std::vector<Complex> conjugate_halves_then_reals(std::vector<Complex> z, const char* what) {
  const double tol = 100.0 * std::numeric_limits<double>::epsilon();
  std::stable_sort(z.begin(), z.end(), [](const Complex& a, const Complex& b) {
    if (a.real() != b.real()) return a.real() < b.real();
    return std::abs(a.imag()) < std::abs(b.imag());
  });
  std::vector<Complex> reals, upper, lower;
  for (const Complex& c : z) {
    if (std::abs(c.imag()) <= tol * std::abs(c)) {
      reals.emplace_back(c.real(), 0.0);
    } else if (c.imag() > 0.0) {
      upper.push_back(c);
    } else {
      lower.push_back(c);
    }
  }
  if (upper.size() != lower.size()) {
    throw InvalidArgument(fmt::format("zpk_to_sos: the {} contain a complex value without its "
                                      "conjugate; a real filter has conjugate pairs", what));
  }
  // Runs of (approximately) equal real part are sorted by |imag| (as scipy), found on `upper`.
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  for (std::size_t start = 0; start < upper.size();) {
    std::size_t stop = start + 1;
    while (stop < upper.size() &&
           upper[stop].real() - upper[stop - 1].real() <= tol * std::abs(upper[stop - 1])) {
      ++stop;
    }
    runs.emplace_back(start, stop);
    start = stop;
  }
  for (auto* v : {&upper, &lower}) {
    for (const auto& [start, stop] : runs) {
      std::stable_sort(v->begin() + static_cast<std::ptrdiff_t>(start),
                       v->begin() + static_cast<std::ptrdiff_t>(stop),
                       [](const Complex& a, const Complex& b) {
                         return std::abs(a.imag()) < std::abs(b.imag());
                       });
    }
  }
  std::vector<Complex> out;
  out.reserve(upper.size() + reals.size());
  for (std::size_t i = 0; i < upper.size(); ++i) {
    if (std::abs(upper[i] - std::conj(lower[i])) > tol * std::abs(lower[i])) {
      throw InvalidArgument(fmt::format("zpk_to_sos: the {} contain a complex value without its "
                                        "conjugate; a real filter has conjugate pairs", what));
    }
    out.push_back((upper[i] + std::conj(lower[i])) / 2.0);  // average out rounding in the pair
  }
  out.insert(out.end(), reals.begin(), reals.end());
  return out;
}

// Index of the pole closest to the unit circle (the "worst" one), first on ties.
std::size_t index_worst(const std::vector<Complex>& p) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < p.size(); ++i) {
    if (std::abs(1.0 - std::abs(p[i])) < std::abs(1.0 - std::abs(p[best]))) best = i;
  }
  return best;
}

enum class Which { real, complex, any };

// scipy _nearest_real_complex_idx: the element of `from` nearest to `to` of the requested kind.
std::size_t nearest_index(const std::vector<Complex>& from, const Complex& to, Which which) {
  std::size_t best = from.size();
  for (std::size_t i = 0; i < from.size(); ++i) {
    if (which == Which::real && !is_real(from[i])) continue;
    if (which == Which::complex && is_real(from[i])) continue;
    if (best == from.size() || std::abs(from[i] - to) < std::abs(from[best] - to)) best = i;
  }
  if (best == from.size()) {
    throw InvalidArgument("zpk_to_sos: cannot pair the roots (no zero of the kind needed); give "
                          "zeros and poles of a real filter");
  }
  return best;
}

Complex take(std::vector<Complex>& v, std::size_t i) {
  const Complex c = v[i];
  v.erase(v.begin() + static_cast<std::ptrdiff_t>(i));
  return c;
}

// Monic polynomial with up to two roots, real part (numpy.poly of a real or conjugate set).
std::vector<double> poly(const std::vector<Complex>& roots) {
  if (roots.empty()) return {1.0};
  if (roots.size() == 1) return {1.0, -roots[0].real()};
  return {1.0, (-roots[0] - roots[1]).real(), (roots[0] * roots[1]).real()};
}

// scipy _single_zpksos: coefficients right-aligned in the row.
Section single_section(const std::vector<Complex>& z, const std::vector<Complex>& p) {
  double row[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  const std::vector<double> b = poly(z);
  const std::vector<double> a = poly(p);
  for (std::size_t i = 0; i < b.size(); ++i) row[3 - b.size() + i] = b[i];
  for (std::size_t i = 0; i < a.size(); ++i) row[6 - a.size() + i] = a[i];
  return Section{row[0], row[1], row[2], row[3], row[4], row[5]};
}

std::size_t count_real(const std::vector<Complex>& v) {
  return static_cast<std::size_t>(std::count_if(v.begin(), v.end(), is_real));
}

}  // namespace

std::vector<Section> zpk_to_sos(const Zpk& zpk) {
  if (!std::isfinite(zpk.gain)) throw_invalid("zpk.gain", zpk.gain, "a finite number");
  for (const auto* list : {&zpk.zeros, &zpk.poles}) {
    for (const Complex& c : *list) {
      if (!std::isfinite(c.real()) || !std::isfinite(c.imag())) {
        throw InvalidArgument("zpk_to_sos: a zero or pole is not finite");
      }
    }
  }
  if (zpk.zeros.empty() && zpk.poles.empty()) {
    return {Section{zpk.gain, 0.0, 0.0, 1.0, 0.0, 0.0}};
  }
  // Pairing 'nearest' (scipy's digital default): equal counts, padded with roots at the origin;
  // an odd count gets one more pole and zero at the origin.
  std::vector<Complex> z = zpk.zeros;
  std::vector<Complex> p = zpk.poles;
  const std::size_t n = std::max(z.size(), p.size());
  z.resize(n, Complex{0.0, 0.0});
  p.resize(n, Complex{0.0, 0.0});
  const std::size_t n_sections = (n + 1) / 2;
  if (n % 2 == 1) {
    z.emplace_back(0.0, 0.0);
    p.emplace_back(0.0, 0.0);
  }
  z = conjugate_halves_then_reals(std::move(z), "zeros");
  p = conjugate_halves_then_reals(std::move(p), "poles");

  std::vector<Section> sos(n_sections);
  // Build from the last section backwards, so the poles nearest the unit circle come last.
  for (std::size_t si = n_sections; si-- > 0;) {
    const Complex p1 = take(p, index_worst(p));
    if (is_real(p1) && count_real(p) == 0) {
      // Last remaining real pole: pair it with the nearest real zero (plus a root at 0).
      const Complex z1 = take(z, nearest_index(z, p1, Which::real));
      sos[si] = single_section({z1, 0.0}, {p1, 0.0});
    } else if (p.size() + 1 == z.size() && !is_real(p1) && count_real(p) == 1 &&
               count_real(z) == 1) {
      // One real pole and one real zero left: this complex pole must take a complex zero.
      const Complex z1 = take(z, nearest_index(z, p1, Which::complex));
      sos[si] = single_section({z1, std::conj(z1)}, {p1, std::conj(p1)});
    } else {
      Complex p2;
      if (is_real(p1)) {
        std::vector<std::size_t> real_idx;
        std::vector<Complex> real_p;
        for (std::size_t i = 0; i < p.size(); ++i) {
          if (is_real(p[i])) {
            real_idx.push_back(i);
            real_p.push_back(p[i]);
          }
        }
        p2 = take(p, real_idx[index_worst(real_p)]);
      } else {
        p2 = std::conj(p1);
      }
      if (!z.empty()) {
        const Complex z1 = take(z, nearest_index(z, p1, Which::any));
        if (!is_real(z1)) {
          sos[si] = single_section({z1, std::conj(z1)}, {p1, p2});
        } else if (!z.empty()) {
          const Complex z2 = take(z, nearest_index(z, p1, Which::real));
          sos[si] = single_section({z1, z2}, {p1, p2});
        } else {
          sos[si] = single_section({z1}, {p1, p2});
        }
      } else {
        sos[si] = single_section({}, {p1, p2});
      }
    }
  }
  Section& first = sos.at(0);  // the gain goes into the first section
  first.b0 *= zpk.gain;
  first.b1 *= zpk.gain;
  first.b2 *= zpk.gain;
  return sos;
}

}  // namespace clearshape::dsp
