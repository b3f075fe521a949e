#include "../src/engine.inl"
