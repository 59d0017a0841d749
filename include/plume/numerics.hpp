// plume/numerics.hpp - the numerics module: element types, concepts, masks, constants,
// per-element functions, transcendental functions and reductions; the math functions over
// spans (spans.hpp) and the choice of instruction set for dispatched entry points (isa.hpp).
//
// Call plume's functions qualified (plume::min, plume::select, plume::any): xsimd defines
// functions of the same names, and for batch arguments an unqualified call finds those by
// argument-dependent lookup, either ambiguously or, worse, silently (xsimd::min follows the
// minps NaN rule, not plume's).
#pragma once

#include <plume/config.hpp>
#include <plume/numerics/approx.hpp>
#include <plume/numerics/bits.hpp>
#include <plume/numerics/concepts.hpp>
#include <plume/numerics/constants.hpp>
#include <plume/numerics/exp_log.hpp>
#include <plume/numerics/functions.hpp>
#include <plume/numerics/hypot.hpp>
#include <plume/numerics/isa.hpp>
#include <plume/numerics/mask.hpp>
#include <plume/numerics/memory.hpp>
#include <plume/numerics/reduce.hpp>
#include <plume/numerics/spans.hpp>
#include <plume/numerics/traits.hpp>
#include <plume/numerics/transpose.hpp>
#include <plume/numerics/trig.hpp>
#include <plume/numerics/wide.hpp>
