# What would happen if the green cube were much heavier? | The purple pulley would not move
# expected: yes

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    green_cube = rope_scene.find("green cube")
    purple_pulley = rope_scene.find("purple pulley")

    cf_init_event = rope_scene.register_event(green_cube, "increase", "mass")
    rope_cf_scene = rope_scene.init_dyn_simulation(cf_init_event)

    # "would not move" is the target 'stationary' (for rotation: "would not rotate").
    flag = rope_cf_scene.happen(purple_pulley, "motion", "stationary")
    return bool_to_yesno(flag)
