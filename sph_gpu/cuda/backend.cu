#include "../src/backend.inl"
