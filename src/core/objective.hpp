// Objectives, the compiled twin of src/optri/objective.py: how triangle weights add up.
//
// The Python side passes optri.objective.ObjectiveCode's ints: the objective as a whole
// (sum, max, or a lexicographic pair) and, for a pair, each component's rule (sum or max).
// Header-only: every part of the core includes it.
#pragma once

#include <cmath>
#include <limits>

#include "weights.hpp"

namespace optri {

// optri.objective.ObjectiveCode. A component of a pair is sum or max.
enum class Objective : int { sum = 0, max = 1, lex = 2 };

// optri.objective.LEX_TIE_RTOL: leading components of a lexicographic objective within
// this relative distance tie, and the next component decides.
constexpr double LEX_TIE_RTOL = 1e-12;

// The cost of a split from its two halves a, b (table values: float or double) and its
// triangle's weight w, under component rule `max` (else sum). The halves are added in
// their own type first, then w in double (numba's promotion, which the engines keep).
template <class T>
inline double combine(bool is_max, T a, T b, double w) {
    if (is_max) return py_max(static_cast<double>(a), py_max(static_cast<double>(b), w));
    return a + b + w;
}

// Whether (a1, a2) is lexicographically below (b1, b2), the first components tied within
// LEX_TIE_RTOL (objective.lex_better).
inline bool lex_better(double a1, double a2, double b1, double b2) {
    if (a1 != b1) {
        const double inf = std::numeric_limits<double>::infinity();
        if (std::fabs(a1) == inf || std::fabs(b1) == inf) return a1 < b1;
        double tol = LEX_TIE_RTOL * py_max(std::fabs(a1), std::fabs(b1));
        if (a1 < b1 - tol) return true;
        if (a1 > b1 + tol) return false;
    }
    return a2 < b2;
}

}  // namespace optri
