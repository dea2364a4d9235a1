#include "app/cli.h"

int main(int argc, char** argv) { return clpt::run_cli(argc, argv); }
