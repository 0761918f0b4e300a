#version 330 core
/* Old version of this file:
void main() { gl_Position = vec4(0.0); }
#version 110
*/
// void main() is below; gl_Position = mvp * p; is what it does. main main main
layout(location = 0) in vec3 p; // the mainline position, not main()
uniform mat4 mvp; /* main */
void main_helper_not_main() {}
void main() // main
{
    main_helper_not_main();
    gl_Position = mvp * vec4(p, 1.0); // gl_Position = vec4(1.0);
}
