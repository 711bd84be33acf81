#include "valerant/explore/turn_back.h"

#include <cmath>

namespace valerant {

bool turnsBack(double last_turn_deg, double turn_deg, double min_turn_deg) {
  const bool opposite = (last_turn_deg > 0 && turn_deg < 0) || (last_turn_deg < 0 && turn_deg > 0);
  return opposite && std::abs(last_turn_deg + turn_deg) < min_turn_deg;
}

}  // namespace valerant
