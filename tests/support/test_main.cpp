// Entry point of every CppUTest executable: floating-point divide-by-zero, overflow, underflow
// and invalid operations raised inside a test fail that test where the fault starts.
#include "CppUTest/CommandLineTestRunner.h"
#include "CppUTest/TestRegistry.h"
#include "CppUTestExt/IEEE754ExceptionsPlugin.h"

int main(int argc, char** argv) {
  IEEE754ExceptionsPlugin ieee754_plugin("IEEE754");
  TestRegistry::getCurrentRegistry()->installPlugin(&ieee754_plugin);
  return CommandLineTestRunner::RunAllTests(argc, argv);
}
