#version 430 core
// Shared constants (included once per program).
const float PI = 3.14159265358979323846;
