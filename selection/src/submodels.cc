#include "gmwm/selection/submodels.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <utility>

#include "gmwm/engine/check.h"

namespace gmwm::selection {
namespace {

// Processes are the same slot type when name and structure agree ("AR1", "ARMA p=2,q=1").
std::string type_key(const Component& c) { return c.process->name() + "(" + c.process->structure() + ")"; }

std::vector<ProcessGroup> group_components(const Model& canonical) {
  std::vector<ProcessGroup> groups;
  std::map<std::string, std::size_t> index;
  for (const Component& c : canonical.components()) {
    const auto [it, added] = index.emplace(type_key(c), groups.size());
    if (added) groups.push_back({c, 0});
    ++groups[it->second].slots;
  }
  return groups;
}

Model build(const std::vector<ProcessGroup>& groups, const std::vector<int>& counts) {
  std::vector<Component> comps;
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (int k = 0; k < counts[g]; ++k) comps.push_back(groups[g].prototype);
  return Model(std::move(comps)).canonical();
}

}  // namespace

int SubModelSet::find(const std::vector<int>& counts) const {
  for (std::size_t i = 0; i < models.size(); ++i)
    if (models[i].counts == counts) return static_cast<int>(i);
  return -1;
}

SubModelSet enumerate_submodels(const Model& maximal) {
  if (maximal.num_components() == 0) throw InvalidArgument("enumerate_submodels: the maximal model is empty");
  SubModelSet set;
  set.groups = group_components(maximal.canonical());
  const std::size_t G = set.groups.size();
  // Every counts vector in [0, slots_g]^G, as a mixed-radix number.
  std::vector<std::vector<int>> all;
  std::vector<int> c(G, 0);
  while (true) {
    std::size_t g = 0;
    while (g < G && c[g] == set.groups[g].slots) c[g++] = 0;
    if (g == G) break;
    ++c[g];
    all.push_back(c);
  }
  auto size_of = [](const std::vector<int>& v) { return std::accumulate(v.begin(), v.end(), 0); };
  std::sort(all.begin(), all.end(), [&](const std::vector<int>& a, const std::vector<int>& b) {
    const int sa = size_of(a), sb = size_of(b);
    if (sa != sb) return sa < sb;
    return std::lexicographical_compare(b.begin(), b.end(), a.begin(), a.end());  // more of earlier first
  });
  std::map<std::vector<int>, int> where;
  for (const auto& counts : all) {
    SubModel m;
    m.counts = counts;
    m.size = size_of(counts);
    m.model = build(set.groups, counts);
    for (std::size_t g = 0; g < G; ++g) {
      if (counts[g] == 0) continue;
      std::vector<int> p = counts;
      --p[g];
      if (const auto it = where.find(p); it != where.end()) m.parents.push_back(it->second);
    }
    where.emplace(counts, static_cast<int>(set.models.size()));
    set.models.push_back(std::move(m));
  }
  return set;
}

Model common_supermodel(const std::vector<Model>& models) {
  if (models.empty()) throw InvalidArgument("common_supermodel: no models given");
  std::vector<ProcessGroup> groups;
  std::map<std::string, std::size_t> index;
  for (const Model& m : models) {
    std::map<std::string, int> here;
    for (const Component& c : m.components()) ++here[type_key(c)];
    for (const Component& c : m.components()) {
      const auto [it, added] = index.emplace(type_key(c), groups.size());
      if (added) groups.push_back({c, 0});
      groups[it->second].slots = std::max(groups[it->second].slots, here[type_key(c)]);
    }
  }
  std::vector<int> counts;
  for (const auto& g : groups) counts.push_back(g.slots);
  return build(groups, counts);
}

std::string difference(const SubModelSet& set, int model, int sub) {
  const auto& a = set.models[static_cast<std::size_t>(model)].counts;
  const auto& b = set.models[static_cast<std::size_t>(sub)].counts;
  std::string out;
  for (std::size_t g = 0; g < set.groups.size(); ++g) {
    const int extra = a[g] - b[g];
    if (extra <= 0) continue;
    if (!out.empty()) out += "+";
    if (extra > 1) out += std::to_string(extra) + "*";
    out += set.groups[g].prototype.process->name();
  }
  return out;
}

}  // namespace gmwm::selection
