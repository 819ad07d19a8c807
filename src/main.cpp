/// The penumbra command-line program: all work happens in app/.
#include "penumbra/app/cli.h"

int main(int argc, char** argv) { return penumbra::app::run_cli(argc, argv); }
