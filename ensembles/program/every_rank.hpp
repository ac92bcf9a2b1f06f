#pragma once
// Over several ranks (qmaps-mpi), a step that may fail on some ranks alone (a configuration, a
// path; nothing collective inside) fails on every rank with the lowest failing rank's error, so
// that all end alike, before anything is written. Alone, the step itself.
#include <exception>

#include "core/error.hpp"
#include "ensembles/io/ranks.hpp"

namespace qmaps {

template <class Step>
void on_every_rank(Step step) {
  if (ranks::count() == 1) return step();
  ranks::Failure mine;
  try {
    step();
  } catch (const Error& e) {
    mine = {static_cast<int>(e.code()), e.what()};
  } catch (const std::exception& e) {
    mine = {static_cast<int>(ExitCode::failure), e.what()};
  }
  const ranks::Failure first = ranks::first_failure(mine);
  if (first.code != 0)
    throw ranks::FailedOnEveryRank(static_cast<ExitCode>(first.code), first.message);
}

}  // namespace qmaps
