// The `mbgen` command.
#include <cstdio>

int main() { return 0; }
