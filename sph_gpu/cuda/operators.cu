#include "../src/operators.inl"
