#include "core/ensemble.hpp"

#include "core/error.hpp"

namespace qmaps {

Ensemble::Ensemble(std::size_t n, std::size_t state_size,
                   const std::vector<std::vector<ColumnSpec>>& measured)
    : orbits(n), padded((n + padding - 1) / padding * padding) {
  if (n == 0) throw usage_error("an ensemble needs at least one orbit");
  for (std::size_t k = 0; k < state_size; ++k) state.emplace_back(padded);
  escape_step = AlignedArray<std::int64_t>(padded, -1);
  escape_reason = AlignedArray<std::uint8_t>(padded, 0);
  for (const auto& specs : measured) {
    first_column_.push_back(column_specs.size());
    for (const auto& spec : specs) {
      column_specs.push_back(spec);
      columns.emplace_back(padded);
    }
  }
  first_column_.push_back(column_specs.size());
}

void Ensemble::set_orbit(std::size_t i, const Ensemble& from, std::size_t j) {
  for (std::size_t k = 0; k < state.size(); ++k) state[k][i] = from.state[k][j];
  escape_step[i] = from.escape_step[j];
  escape_reason[i] = from.escape_reason[j];
  for (std::size_t c = 0; c < columns.size(); ++c) columns[c][i] = from.columns[c][j];
}

void Ensemble::fill_padding() {
  for (std::size_t i = orbits; i < padded; ++i) set_orbit(i, *this, orbits - 1);
}

std::size_t Ensemble::escaped() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < orbits; ++i) n += escape_step[i] >= 0;
  return n;
}

}  // namespace qmaps
