# What can we do to let most of the pink fluid enter black container? | Remove green stick
# runnable: no (the paper's listing eg2; fluid scenes have no backend in this version)

def execute_command(video):
    fluid_scene = SoftScene(video, 'fluid')
    pink_fluid = fluid_scene.find("pink fluid")
    black_container = fluid_scene.find("black container")

    gd_init_event = fluid_scene.register_event([], "remove", "green stick")
    fluid_gd_scene = fluid_scene.init_dyn_simulation(gd_init_event)

    flag = fluid_gd_scene.happen([pink_fluid], "entering", [black_container])

    return bool_to_yesno(flag)
