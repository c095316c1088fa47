# What can we do to let most of the pink fluid enter the green container? | Remove the brown stick
# expected: yes

def execute_command(video):
    fluid_scene = SoftScene(video, 'fluid')
    pink_fluid = fluid_scene.find("pink fluid")
    green_container = fluid_scene.find("green container")

    # The option is an event: remove the brown stick, then check the goal in that scene.
    gd_init_event = fluid_scene.register_event([], "remove", "brown stick")
    fluid_gd_scene = fluid_scene.init_dyn_simulation(gd_init_event)

    # "most of the fluid": more of it ends in this container than in any other.
    flag = fluid_gd_scene.happen([pink_fluid], "entering most", [green_container])

    return bool_to_yesno(flag)
