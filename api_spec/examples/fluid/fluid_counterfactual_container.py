# If the brown stick were removed, which container would light blue fluid flow into? | Green container
# expected: yes

def execute_command(video):
    fluid_scene = SoftScene(video, 'fluid')
    light_blue_fluid = fluid_scene.find("light blue fluid")
    green_container = fluid_scene.find("green container")

    cf_init_event = fluid_scene.register_event([], "remove", "brown stick")
    fluid_cf_scene = fluid_scene.init_dyn_simulation(cf_init_event)

    # "entering" holds for every container some of the fluid ends in, even a small part.
    flag = fluid_cf_scene.happen(light_blue_fluid, "entering", green_container)
    return bool_to_yesno(flag)
