#pragma once
// A stop asked by a signal (Ctrl-C, SIGTERM, SIGHUP when the terminal
// closes or the ssh connection drops, SIGPIPE when standard output's reader
// is gone). Its own room because the handler may only touch a lock-free
// flag, and every long wait of the console (a run, a script, the tuner, a
// port that is not there yet) polls the same one.
#include <csignal>
#include <string>

namespace nlsoft::console {

// From the signal handler: a run_for() stops its run early and the script
// runner stops before its next command. Async-signal-safe.
void request_interrupt(int signal = SIGINT);
bool interrupted();
// "interrupted by SIGHUP (the terminal closed)": what the run's end and
// the console's last message say.
std::string interrupt_reason();

}  // namespace nlsoft::console
