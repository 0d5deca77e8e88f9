#version 430 core
// Depth of the mesh seen from a light. Cube maps and the spot and point
// lights' 2D maps store the distance to the light over u_far; directional
// maps the projected (orthographic, so linear) depth.
layout(location = 0) in vec4 a_position;

uniform mat4 u_model;       // model units to the scene's world (identity for now)
uniform mat4 u_view_proj;   // the light's view-projection for this face
out vec3 v_world;

void main()
{
    vec4 world = u_model * vec4(a_position.xyz, 1.0);
    v_world = world.xyz;
    gl_Position = u_view_proj * world;
}
