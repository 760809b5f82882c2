// The one way core/ times a span of its work: a ScopedTimer starts a timer of the run's
// Teuchos::StackedTimer (timers.txt, summary.csv's *_seconds) when constructed and stops it at the end
// of its scope, also when the scope is left by an exception, so a timer is never left running (the
// stacked timers must stop in the order they started). A null timer times nothing.
#pragma once
#include <string>
#include <utility>

#include <Teuchos_RCP.hpp>
#include <Teuchos_StackedTimer.hpp>

namespace bc::core {

class ScopedTimer {
 public:
  ScopedTimer(Teuchos::RCP<Teuchos::StackedTimer> timer, std::string name)
      : timer_(std::move(timer)), name_(std::move(name)) {
    if (!timer_.is_null()) timer_->start(name_);
  }
  ~ScopedTimer() { stop(); }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;
  // Stops the timer before the end of the scope (once; the destructor then does nothing).
  void stop() {
    if (!timer_.is_null()) timer_->stop(name_);
    timer_ = Teuchos::null;
  }

 private:
  Teuchos::RCP<Teuchos::StackedTimer> timer_;
  std::string name_;
};

}  // namespace bc::core
