// stub
#include <cstdio>
int main() { std::puts("lever: not yet"); return 0; }
