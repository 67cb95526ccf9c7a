// Looking a name up in registry tables: the one look-up behind find_estimator
// (estimators/registry.cpp) and find_integrand (integrands/registry.cpp), so that both say the
// same thing about an unknown name.
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

namespace pcbench {

// The first entry named `name` in `tables`, searched in order, or nullptr. Every name seen is
// appended to `names` in table order: the valid choices for the caller's message (with
// did_you_mean, base/nearest_name.h), which may still try other sources before it refuses.
template <class Entry>
const Entry* find_by_name(std::initializer_list<const std::vector<Entry>*> tables,
                          const std::string& name, std::vector<std::string>& names) {
  for (const std::vector<Entry>* table : tables) {
    for (const Entry& entry : *table) {
      if (entry.name == name) return &entry;
      names.push_back(entry.name);
    }
  }
  return nullptr;
}

}  // namespace pcbench
