# If we want the gray pulley to rotate anti-clockwise, what can we do? | Increase the mass of the purple cube
# expected: yes

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    purple_cube = rope_scene.find("purple cube")
    gray_pulley = rope_scene.find("gray pulley")

    # The option is the event; the goal is what must happen in the dynamic scene it starts.
    gd_init_event = rope_scene.register_event(purple_cube, "increase", "mass")
    rope_gd_scene = rope_scene.init_dyn_simulation(gd_init_event)

    flag = rope_gd_scene.happen(gray_pulley, "rotation", "anti-clockwise")
    return bool_to_yesno(flag)
