"""The code of a robot's mechanisms (robospec.model.mechanisms) in its agent class.

- Closed loops: in ``_after_loading_articulation``, one ``scene.create_drive`` between the two
  links at their meeting frames with all translation limits zero, as ManiSkill's Robotiq
  agents close their four-bars (``create_drive`` builds one PhysX drive per sub-scene: the
  same code serves the CPU and the GPU); a weld also locks the relative rotation, on each
  sub-scene's drive (ManiSkill's ``Drive`` has translation limits only).
- Touch sensors: ``get_fsr_impulse()`` and ``get_fsr_obj_impulse(obj)`` as ManiSkill's
  ``AllegroHandRightTouch`` writes them, its CPU path (the scene's contact list) and its GPU
  path (contact impulse queries, made once and kept), and their magnitudes in the
  proprioception when the spec asks.
- A planar base needs no code of its own: its controller, its collision bits and the derived
  description are the agent's ordinary data.
"""

from __future__ import annotations

import ast

from robospec.emit.members import function, link_expr, template
from robospec.emit.values import const
from robospec.resolve.resolved import ResolvedRobot

# the members touch sensors add to the class (ManiSkill's names)
TOUCH_MEMBERS = ("fsr_links", "pair_query", "body_query", "get_fsr_impulse", "get_fsr_obj_impulse")
TOUCH_READING = "fsr_impulse"  # the proprioception's key (ManiSkill's)


def loop_statements(robot: ResolvedRobot) -> list[ast.stmt]:
    """``_after_loading_articulation`` statements closing every loop."""
    body: list[ast.stmt] = []
    for loop in robot.loops:
        (p0, q0), (p1, q1) = loop.poses
        body += template(
            """
            loop = self.scene.create_drive(
                FIRST, sapien.Pose(FIRST_P, FIRST_Q), SECOND, sapien.Pose(SECOND_P, SECOND_Q)
            )
            loop.set_limit_x(0, 0)
            loop.set_limit_y(0, 0)
            loop.set_limit_z(0, 0)
            """,
            FIRST=link_expr(loop.links[0], None),
            FIRST_P=const(list(p0)),
            FIRST_Q=const(list(q0)),
            SECOND=link_expr(loop.links[1], None),
            SECOND_P=const(list(p1)),
            SECOND_Q=const(list(q1)),
        )
        if loop.weld:
            body += template(
                """
                for drive in loop._objs:
                    drive.set_limit_twist(0, 0)
                    drive.set_limit_pyramid(0, 0, 0, 0)
                """
            )
    return body


def touch_after_init(robot: ResolvedRobot) -> list[ast.stmt]:
    """``_after_init`` statements binding the sensing links and the (GPU) query caches."""
    if robot.touch is None:
        return []
    return template(
        """
        self.fsr_links = [self.robot.links_map[name] for name in LINKS]
        self.pair_query = dict()
        self.body_query = None
        """,
        LINKS=const(list(robot.touch.links)),
    )


def touch_methods(robot: ResolvedRobot) -> list[ast.stmt]:
    """``get_fsr_obj_impulse`` and ``get_fsr_impulse``, ManiSkill's own code."""
    if robot.touch is None:
        return []
    obj_impulse = function(
        "get_fsr_obj_impulse",
        '''
        def get_fsr_obj_impulse(self, obj=None):
            """The contact impulse between each sensing link and ``obj``."""
            if self.scene.gpu_sim_enabled:
                px = self.scene.px
                if obj.name not in self.pair_query:
                    bodies = list(zip(*[link._bodies for link in self.fsr_links]))
                    bodies = list(itertools.chain(*bodies))
                    obj_bodies = [
                        elem for item in obj._bodies for elem in itertools.repeat(item, 2)
                    ]
                    body_pairs = list(zip(bodies, obj_bodies))
                    query = px.gpu_create_contact_pair_impulse_query(body_pairs)
                    shape = [len(obj._bodies), len(self.fsr_links), 3]
                    self.pair_query[obj.name] = (query, tuple(shape))
                query = self.pair_query[obj.name][0]
                contacts_shape = self.pair_query[obj.name][1]
                px.gpu_query_contact_pair_impulses(query)
                impulses = query.cuda_impulses.torch().clone()
                return impulses.reshape((len(self.fsr_links), *contacts_shape))
            internal_fsr_links = [link._bodies[0].entity for link in self.fsr_links]
            contacts = self.scene.get_contacts()
            obj_contacts = sapien_utils.get_multiple_pairwise_contacts(
                contacts, obj._bodies[0].entity, internal_fsr_links
            )
            sorted_contacts = [obj_contacts[link] for link in internal_fsr_links]
            contact_forces = [
                sapien_utils.compute_total_impulse(contact) for contact in sorted_contacts
            ]
            return np.stack(contact_forces)
        ''',
    )
    impulse = function(
        "get_fsr_impulse",
        '''
        def get_fsr_impulse(self):
            """Each sensing link's total contact impulse: [envs, links, 3]."""
            if self.scene.gpu_sim_enabled:
                px = self.scene.px
                if self.body_query is None:
                    bodies = list(zip(*[link._bodies for link in self.fsr_links]))
                    bodies = list(itertools.chain(*bodies))
                    query = px.gpu_create_contact_body_impulse_query(bodies)
                    shape = [len(self.fsr_links[0]._bodies), len(self.fsr_links), 3]
                    self.body_query = (query, tuple(shape))
                query = self.body_query[0]
                contacts_shape = self.body_query[1]
                px.gpu_query_contact_body_impulses(query)
                return query.cuda_impulses.torch().clone().reshape(*contacts_shape)
            internal_fsr_links = [link._bodies[0].entity for link in self.fsr_links]
            contacts = self.scene.get_contacts()
            contact_map = sapien_utils.get_cpu_actors_contacts(contacts, internal_fsr_links)
            sorted_contacts = [contact_map[link] for link in internal_fsr_links]
            contact_forces = [
                sapien_utils.compute_total_impulse(contact) for contact in sorted_contacts
            ]
            return torch.from_numpy(np.stack(contact_forces)[None, ...])
        ''',
    )
    return [obj_impulse, impulse]


def touch_reading(robot: ResolvedRobot) -> tuple[ast.expr, ast.expr] | None:
    """The proprioception's ``fsr_impulse`` entry (key, value), when the spec asks for it."""
    if robot.touch is None or not robot.touch.proprioception:
        return None
    (stmt,) = template("torch.linalg.norm(self.get_fsr_impulse(), dim=-1)")
    assert isinstance(stmt, ast.Expr)
    return ast.Constant(TOUCH_READING), stmt.value
