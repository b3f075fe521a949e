#include "../src/neighbor_search.inl"
