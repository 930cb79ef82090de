// Whether qemu-user can run a program that starts a thread on this host (qemu
// 7.2 hangs in pthread_create under some host kernels): run_tests.sh runs it
// under qemu-aarch64 with a time limit before the threaded aarch64 tests.
#include <cstdio>
#include <thread>

int main() {
  int value = 0;
  std::thread t([&] { value = 1; });
  t.join();
  std::printf("thread_probe: %d\n", value);
  return value == 1 ? 0 : 1;
}
