#include "signal_cancellation.h"

#include <cstdlib>

namespace tessera {

void SignalCancellation::on_signal(int number) {
  int none = 0;
  if (!signal_.compare_exchange_strong(none, number)) std::_Exit(128 + number);
  cancel_.cancel();
}

}  // namespace tessera
