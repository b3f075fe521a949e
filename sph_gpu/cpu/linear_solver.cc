#include "../src/linear_solver.inl"
