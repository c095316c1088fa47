# If the purple cube were much lighter, what would happen? | The blue pulley would rotate clockwise
# expected: yes

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    purple_cube = rope_scene.find("purple cube")
    blue_pulley = rope_scene.find("blue pulley")

    # "much lighter" is a counterfactual: decrease the mass of the purple cube.
    cf_init_event = rope_scene.register_event(purple_cube, "decrease", "mass")
    rope_cf_scene = rope_scene.init_dyn_simulation(cf_init_event)

    flag = rope_cf_scene.happen(blue_pulley, "rotation", "clockwise")
    return bool_to_yesno(flag)
