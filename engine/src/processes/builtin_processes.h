#pragma once
// Every built-in process type, by its class name. The registry (process_registry.cc) is
// built from this list at its first use; each type's file defines its
// register_process_<Type> with GMWM_REGISTER_PROCESS. Adding a process: its file, one
// entry here, and its test.
#define GMWM_BUILTIN_PROCESSES(X) \
  X(Ar1Process)                   \
  X(ArmaProcess)                  \
  X(Arma11Process)                \
  X(Drift)                        \
  X(Flicker)                      \
  X(GaussMarkov)                  \
  X(Ma1Process)                   \
  X(QuantizationNoise)            \
  X(RandomWalk)                   \
  X(Sinusoid)                     \
  X(WhiteNoise)
