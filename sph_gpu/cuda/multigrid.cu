#include "../src/multigrid.inl"
