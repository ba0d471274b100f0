// msm_lab: command-line virtual materials lab (see docs/lab.md).
// Exit codes: 0 success, 1 the experiment failed (or a hardness outside its conversion's range),
// 2 bad arguments.
#include <iostream>
#include <string>
#include <vector>

#include "lab_main.h"

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv, argv + argc);
  return msm_sim::lab::RunLabMain(args, std::cout, std::cerr);
}
