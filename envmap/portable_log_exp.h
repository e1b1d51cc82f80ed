// Natural logarithm and exponential with the same bits on every machine, for the per-frame
// path (design §3: no libm there; glibc picks FMA or non-FMA code per CPU). Only IEEE +, −, ×, ÷
// in a fixed order, and frexp/ldexp (exact). Within a few ulp of the true value.
#pragma once

namespace penumbra::envmap {

// ln x for x > 0 finite; −∞ for 0, NaN for negative or NaN input, +∞ for +∞.
double portableLog(double x);

// e^x; 0 below −745, +∞ above 709.78, NaN for NaN.
double portableExp(double x);

}  // namespace penumbra::envmap
