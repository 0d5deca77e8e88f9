#version 430 core
// sam_view: text and panels in window pixels, (0, 0) at the top left.
layout(location = 0) in vec2 a_pixel;
layout(location = 1) in vec4 a_color;
uniform vec2 u_window;
out vec4 v_color;
void main()
{
    v_color = a_color;
    gl_Position = vec4(2.0 * a_pixel.x / u_window.x - 1.0, 1.0 - 2.0 * a_pixel.y / u_window.y, 0.0, 1.0);
}
