#pragma once
// The Quake III length convention: 32 game units are one metre (a 56-unit player hull
// is 1.75 m tall). Every conversion between engine units and metres uses this one
// constant; it is an engine fact, not a tuning value, so no configuration sets it.
namespace valerant::quake3 {

constexpr double kUnitsPerMetre = 32.0;

}  // namespace valerant::quake3
