#version 430 core
// sam_view: the back-side samples of the vertex under the cursor, as lines in model space.
layout(location = 0) in vec3 a_position;
uniform mat4 u_view_proj;
uniform vec2 u_shift; // in NDC, to widen lines by drawing shifted copies
void main()
{
    gl_Position = u_view_proj * vec4(a_position, 1.0);
    gl_Position.xy += u_shift * gl_Position.w;
    gl_PointSize = 7.0;
}
