#pragma once
// The registry the research tests draw from: the library's methods plus the oracle starters
// and negative controls of dc_research.
#include "dc/research/research_starters.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc::test {

inline WarmStarterRegistry research_registry() {
  WarmStarterRegistry r = default_warm_starters();
  add_research_starters(r);
  return r;
}

}  // namespace dc::test
