#pragma once
// The steps at which a run samples its orbits (invariants, densities): every multiple of the
// stride, and the run's last step. A run cut into segments (checkpoint and resume) samples exactly
// as the uninterrupted run. One object answers for a block's single steps, its chunks and their
// replays (core/block.hpp), so that the rule is written once.
#include "core/run_plan.hpp"

namespace qmaps {

// The samples a chunk takes while its chains are in registers: after its steps at, at + stride,
// ... (counted from 1), each only where the escape test holds up to it, so that a sample taken is
// one the reference takes. `through`: the chunk's last step sampled.
struct ChunkSamples {
  long long at, stride, through = 0;
};

class SampleSchedule {
 public:
  // `sampling`: whether anything is sampled at all (else no step is).
  SampleSchedule(const RunPlan& plan, bool sampling)
      : stride_(plan.stride), total_(plan.total), sampling_(sampling) {
    reach(plan.first);
  }

  // Whether step n is sampled.
  bool at(long long n) const { return sampling_ && (n % stride_ == 0 || n == total_); }
  // Whether the single step to `next` (one after the last reached) is sampled; reaches it, with
  // no division.
  bool single_step(long long next) {
    const bool multiple = next == next_multiple_;
    if (multiple) next_multiple_ += stride_;
    return sampling_ && (multiple || next == total_);
  }
  // The samples of the chunk of steps n + 1 .. next, n the step last reached.
  ChunkSamples chunk(long long n, long long next) const {
    return {sampling_ ? next_multiple_ - n : next - n + 1, stride_};
  }
  // Whether the chunk's end `next`, proved clean, is sampled after it: the run's last step where
  // it is no multiple (a chunk samples only the multiples in it).
  bool after_chunk(long long next) const {
    return sampling_ && next == total_ && next % stride_ != 0;
  }
  // Whether step j of the chunk from step n, replayed after `taken`, is sampled in the replay.
  bool in_replay(long long j, long long n, const ChunkSamples& taken) const {
    return j > n + taken.through && at(j);
  }
  // Moves on to step n after a chunk.
  void reach(long long n) { next_multiple_ = (n / stride_ + 1) * stride_; }

 private:
  long long stride_, total_;
  bool sampling_;
  long long next_multiple_ = 0;  // the first multiple of the stride after the step last reached
};

}  // namespace qmaps
