// One process: qmaps. (qmaps-mpi links ensembles/io/ranks_mpi.cpp instead.)
#include "ensembles/io/ranks.hpp"

#include <cstdlib>

namespace qmaps::ranks {

int rank() { return 0; }
int count() { return 1; }
void sum(std::span<std::int64_t>) {}
std::int64_t sum(std::int64_t value) { return value; }
std::int64_t before(std::int64_t) { return 0; }
std::int64_t max(std::int64_t value) { return value; }
double min(double value) { return value; }
double max(double value) { return value; }
std::string from_root(const std::string& value) { return value; }
void from_root(std::span<std::byte>) {}
std::vector<double> gathered(std::span<const double> values) { return {values.begin(), values.end()}; }
std::vector<std::string> gathered(const std::string& value) { return {value}; }
Failure first_failure(const Failure& mine) { return mine; }
void barrier() {}
void abort(int code) { std::_Exit(code); }

}  // namespace qmaps::ranks
