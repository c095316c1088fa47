# Which direction would the gray pulley rotate if the pink sphere were much lighter? | Stationary
# expected: yes

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    pink_sphere = rope_scene.find("pink sphere")
    gray_pulley = rope_scene.find("gray pulley")

    cf_init_event = rope_scene.register_event(pink_sphere, "decrease", "mass")
    rope_cf_scene = rope_scene.init_dyn_simulation(cf_init_event)

    # Options are 'Clockwise', 'Anti-clockwise', 'Stationary' for rotation and 'Up', 'Down',
    # 'Stationary' for motion; the option word is the target.
    flag = rope_cf_scene.happen(gray_pulley, "rotation", "stationary")
    return bool_to_yesno(flag)
